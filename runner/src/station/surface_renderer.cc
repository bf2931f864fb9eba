// Height-map and burr drawing with one small Lambert shader.
#include "station/surface_renderer.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <string>

namespace burrlab::runner {
namespace {

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in float depth;
uniform mat4 mvp;
uniform mat4 model;
out vec3 v_normal;
out float v_depth;
void main() {
  v_normal = mat3(model) * normal;
  v_depth = depth;
  gl_Position = mvp * vec4(position, 1.0);
}
)";

// Bone-coloured where untouched, darker and redder where material was removed.
constexpr const char* kFragmentShader = R"(#version 330 core
in vec3 v_normal;
in float v_depth;
uniform vec3 base_color;
uniform vec3 cut_color;
out vec4 color;
void main() {
  vec3 n = normalize(v_normal);
  vec3 light = normalize(vec3(-0.4, -0.6, 1.0));
  float lambert = 0.25 + 0.75 * max(dot(n, light), 0.0);
  vec3 albedo = mix(base_color, cut_color, clamp(v_depth, 0.0, 1.0));
  color = vec4(albedo * lambert, 1.0);
}
)";

Result<unsigned> Compile(GLenum type, const char* source) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == 0) {
    char log[1024] = {};
    glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
    glDeleteShader(shader);
    return Error{std::string("cannot compile a shader: ") + log};
  }
  return shader;
}

void SetUpAttributes() {
  const GLsizei stride = 7 * sizeof(float);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(6 * sizeof(float)));
  glEnableVertexAttribArray(2);
}

}  // namespace

Result<std::unique_ptr<SurfaceRenderer>> SurfaceRenderer::Create() {
  Result<unsigned> vs = Compile(GL_VERTEX_SHADER, kVertexShader);
  if (!vs.ok()) return vs.error();
  Result<unsigned> fs = Compile(GL_FRAGMENT_SHADER, kFragmentShader);
  if (!fs.ok()) return fs.error();
  std::unique_ptr<SurfaceRenderer> r(new SurfaceRenderer());
  r->program_ = glCreateProgram();
  glAttachShader(r->program_, vs.value());
  glAttachShader(r->program_, fs.value());
  glLinkProgram(r->program_);
  glDeleteShader(vs.value());
  glDeleteShader(fs.value());
  GLint ok = 0;
  glGetProgramiv(r->program_, GL_LINK_STATUS, &ok);
  if (ok == 0) {
    return Error{"cannot link the surface shader"};
  }
  // A unit UV sphere for the burr.
  constexpr int kRings = 16, kSegments = 32;
  std::vector<float> v;
  std::vector<unsigned> idx;
  for (int ring = 0; ring <= kRings; ++ring) {
    const double theta = M_PI * ring / kRings;
    for (int seg = 0; seg <= kSegments; ++seg) {
      const double phi = 2.0 * M_PI * seg / kSegments;
      const float x = static_cast<float>(std::sin(theta) * std::cos(phi));
      const float y = static_cast<float>(std::sin(theta) * std::sin(phi));
      const float z = static_cast<float>(std::cos(theta));
      v.insert(v.end(), {x, y, z, x, y, z, 0.0f});
    }
  }
  for (int ring = 0; ring < kRings; ++ring) {
    for (int seg = 0; seg < kSegments; ++seg) {
      const unsigned a = static_cast<unsigned>(ring * (kSegments + 1) + seg);
      const unsigned b = a + kSegments + 1;
      idx.insert(idx.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  }
  glGenVertexArrays(1, &r->sphere_vao_);
  glBindVertexArray(r->sphere_vao_);
  glGenBuffers(1, &r->sphere_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, r->sphere_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(v.size() * 4), v.data(),
               GL_STATIC_DRAW);
  glGenBuffers(1, &r->sphere_ibo_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->sphere_ibo_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(idx.size() * 4),
               idx.data(), GL_STATIC_DRAW);
  SetUpAttributes();
  r->sphere_indices_ = static_cast<int>(idx.size());
  glGenVertexArrays(1, &r->skirt_vao_);
  glBindVertexArray(r->skirt_vao_);
  glGenBuffers(1, &r->skirt_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, r->skirt_vbo_);
  SetUpAttributes();
  glGenVertexArrays(1, &r->surface_vao_);
  glGenBuffers(1, &r->surface_vbo_);
  glGenBuffers(1, &r->surface_ibo_);
  glBindVertexArray(0);
  return r;
}

SurfaceRenderer::~SurfaceRenderer() {
  const GLuint buffers[] = {surface_vbo_, surface_ibo_, sphere_vbo_,
                            sphere_ibo_, skirt_vbo_};
  glDeleteBuffers(5, buffers);
  const GLuint arrays[] = {surface_vao_, sphere_vao_, skirt_vao_};
  glDeleteVertexArrays(3, arrays);
  glDeleteProgram(program_);
}

void SurfaceRenderer::Update(const SurfaceSnapshot& snapshot) {
  const HeightMap& map = snapshot.surface;
  if (map.nx < 2 || map.ny < 2) return;
  glBindVertexArray(surface_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, surface_vbo_);
  if (map.nx != mesh_nx_ || map.ny != mesh_ny_) {
    std::vector<unsigned> idx;
    for (int j = 0; j + 1 < map.ny; ++j) {
      for (int i = 0; i + 1 < map.nx; ++i) {
        const unsigned a = static_cast<unsigned>(j * map.nx + i);
        const unsigned b = a + static_cast<unsigned>(map.nx);
        idx.insert(idx.end(), {a, a + 1, b, a + 1, b + 1, b});
      }
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, surface_ibo_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(idx.size() * 4), idx.data(),
                 GL_STATIC_DRAW);
    surface_indices_ = static_cast<int>(idx.size());
    mesh_nx_ = map.nx;
    mesh_ny_ = map.ny;
    vertices_.assign(static_cast<std::size_t>(map.nx) * map.ny * 7, 0.0f);
    SetUpAttributes();
  }
  // The untouched level: the highest column.
  const float top =
      *std::max_element(map.height_mm.begin(), map.height_mm.end());
  const float cell = static_cast<float>(map.cell_mm);
  for (int j = 0; j < map.ny; ++j) {
    for (int i = 0; i < map.nx; ++i) {
      const float h = map.At(i, j);
      const float dx = map.At(std::min(i + 1, map.nx - 1), j) -
                       map.At(std::max(i - 1, 0), j);
      const float dy = map.At(i, std::min(j + 1, map.ny - 1)) -
                       map.At(i, std::max(j - 1, 0));
      glm::vec3 n(-dx / (2.0f * cell), -dy / (2.0f * cell), 1.0f);
      n = glm::normalize(n);
      float* out = &vertices_[(static_cast<std::size_t>(j) * map.nx + i) * 7];
      out[0] = (static_cast<float>(i) + 0.5f) * cell;
      out[1] = (static_cast<float>(j) + 0.5f) * cell;
      out[2] = h;
      out[3] = n.x;
      out[4] = n.y;
      out[5] = n.z;
      out[6] = std::clamp((top - h) / 2.0f, 0.0f, 1.0f);  // 2 mm -> full
    }
  }
  glBufferData(GL_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(vertices_.size() * sizeof(float)),
               vertices_.data(), GL_DYNAMIC_DRAW);
  // The sides: from each border column down to the bottom of the volume.
  skirt_.clear();
  const auto side = [&](int i0, int j0, int di, int dj, int count,
                        glm::vec3 normal) {
    for (int k = 0; k + 1 < count; ++k) {
      const int ia = i0 + k * di, ja = j0 + k * dj;
      const int ib = ia + di, jb = ja + dj;
      const float xa = (static_cast<float>(ia) + 0.5f) * cell;
      const float ya = (static_cast<float>(ja) + 0.5f) * cell;
      const float xb = (static_cast<float>(ib) + 0.5f) * cell;
      const float yb = (static_cast<float>(jb) + 0.5f) * cell;
      const float ha = map.At(ia, ja), hb = map.At(ib, jb);
      const float corners[4][3] = {
          {xa, ya, 0.0f}, {xb, yb, 0.0f}, {xb, yb, hb}, {xa, ya, ha}};
      for (int c : {0, 1, 2, 0, 2, 3}) {
        skirt_.insert(skirt_.end(),
                      {corners[c][0], corners[c][1], corners[c][2], normal.x,
                       normal.y, normal.z, 0.0f});
      }
    }
  };
  side(0, 0, 1, 0, map.nx, {0.0f, -1.0f, 0.0f});
  side(0, map.ny - 1, 1, 0, map.nx, {0.0f, 1.0f, 0.0f});
  side(0, 0, 0, 1, map.ny, {-1.0f, 0.0f, 0.0f});
  side(map.nx - 1, 0, 0, 1, map.ny, {1.0f, 0.0f, 0.0f});
  glBindVertexArray(skirt_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, skirt_vbo_);
  glBufferData(GL_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(skirt_.size() * sizeof(float)),
               skirt_.data(), GL_DYNAMIC_DRAW);
  skirt_vertices_ = static_cast<int>(skirt_.size() / 7);
  glBindVertexArray(0);
  view_.surface.nx = map.nx;
  view_.surface.ny = map.ny;
  view_.surface.cell_mm = map.cell_mm;
  view_.surface.top_mm = map.top_mm;
  view_.burr_mm = snapshot.burr_mm;
  view_.burr_radius_mm = snapshot.burr_radius_mm;
  has_surface_ = true;
}

void SurfaceRenderer::Draw(int x, int y, int width, int height) const {
  glViewport(x, y, width, height);
  glEnable(GL_SCISSOR_TEST);
  glScissor(x, y, width, height);
  glClearColor(0.12f, 0.13f, 0.16f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  if (!has_surface_) return;
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  const HeightMap& map = view_.surface;
  const float sx = static_cast<float>(map.nx * map.cell_mm);
  const float sy = static_cast<float>(map.ny * map.cell_mm);
  const float size = std::max(sx, sy);
  const glm::vec3 centre(sx / 2.0f, sy / 2.0f,
                         static_cast<float>(map.top_mm) * 0.5f);
  const glm::mat4 view =
      glm::lookAt(centre + glm::vec3(-0.55f * size, -1.25f * size, 1.1f * size),
                  centre, glm::vec3(0.0f, 0.0f, 1.0f));
  const glm::mat4 projection = glm::perspective(
      glm::radians(40.0f),
      static_cast<float>(width) / static_cast<float>(std::max(height, 1)),
      0.05f * size, 10.0f * size);
  glUseProgram(program_);
  const GLint mvp_at = glGetUniformLocation(program_, "mvp");
  const GLint model_at = glGetUniformLocation(program_, "model");
  const GLint base_at = glGetUniformLocation(program_, "base_color");
  const GLint cut_at = glGetUniformLocation(program_, "cut_color");
  glm::mat4 model(1.0f);
  glm::mat4 mvp = projection * view * model;
  glUniformMatrix4fv(mvp_at, 1, GL_FALSE, glm::value_ptr(mvp));
  glUniformMatrix4fv(model_at, 1, GL_FALSE, glm::value_ptr(model));
  glUniform3f(base_at, 0.93f, 0.88f, 0.76f);
  glUniform3f(cut_at, 0.75f, 0.35f, 0.30f);
  glBindVertexArray(surface_vao_);
  glDrawElements(GL_TRIANGLES, surface_indices_, GL_UNSIGNED_INT, nullptr);
  glUniform3f(base_at, 0.80f, 0.75f, 0.64f);
  glBindVertexArray(skirt_vao_);
  glDrawArrays(GL_TRIANGLES, 0, skirt_vertices_);
  if (view_.burr_radius_mm > 0.0) {
    const float r = static_cast<float>(view_.burr_radius_mm);
    model =
        glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(view_.burr_mm)),
                   glm::vec3(r));
    mvp = projection * view * model;
    glUniformMatrix4fv(mvp_at, 1, GL_FALSE, glm::value_ptr(mvp));
    glUniformMatrix4fv(model_at, 1, GL_FALSE, glm::value_ptr(model));
    glUniform3f(base_at, 0.55f, 0.65f, 0.80f);
    glUniform3f(cut_at, 0.55f, 0.65f, 0.80f);
    glBindVertexArray(sphere_vao_);
    glDrawElements(GL_TRIANGLES, sphere_indices_, GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
  glDisable(GL_DEPTH_TEST);
}

}  // namespace burrlab::runner
