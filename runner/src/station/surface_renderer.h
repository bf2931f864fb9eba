// OpenGL 3.3 core drawing of the material block's height map (lit, shaded by
// depth so a pit stands out) and the burr sphere, from a SurfaceSnapshot. Needs
// a current GL context; used only by the window.
#ifndef BURRLAB_RUNNER_STATION_SURFACE_RENDERER_H_
#define BURRLAB_RUNNER_STATION_SURFACE_RENDERER_H_

#include <cstdint>
#include <memory>
#include <vector>

#include "burrlab/base/result.h"
#include "station/surface_snapshot.h"

namespace burrlab::runner {

class SurfaceRenderer {
 public:
  // Compiles the shaders; fails with the GL info log.
  static Result<std::unique_ptr<SurfaceRenderer>> Create();
  ~SurfaceRenderer();
  SurfaceRenderer(const SurfaceRenderer&) = delete;
  SurfaceRenderer& operator=(const SurfaceRenderer&) = delete;

  // Rebuilds the surface mesh from the snapshot (the window's thread only).
  void Update(const SurfaceSnapshot& snapshot);
  // Draws into the viewport (x, y from the bottom left, pixels).
  void Draw(int x, int y, int width, int height) const;

 private:
  SurfaceRenderer() = default;
  unsigned program_ = 0;
  unsigned surface_vao_ = 0, surface_vbo_ = 0, surface_ibo_ = 0;
  unsigned sphere_vao_ = 0, sphere_vbo_ = 0, sphere_ibo_ = 0;
  unsigned skirt_vao_ = 0, skirt_vbo_ = 0;  // the block's four sides
  int skirt_vertices_ = 0;
  int surface_indices_ = 0;
  int sphere_indices_ = 0;
  int mesh_nx_ = -1, mesh_ny_ = -1;
  std::vector<float> vertices_;  // x y z nx ny nz depth, reused
  std::vector<float> skirt_;     // same layout, triangles
  SurfaceSnapshot view_;         // geometry of the last update (no heights)
  bool has_surface_ = false;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_SURFACE_RENDERER_H_
