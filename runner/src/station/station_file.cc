// station.toml parsing and checking.
#include "station/station_file.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include "burrlab/stimuli/toml_fields.h"
#include "station/station_toml.h"

namespace burrlab::runner {
namespace {

using protocols::Diagnostic;
using protocols::SourceLocation;

constexpr std::string_view kStationKeys[] = {"format", "device", "response_box",
                                             "screen"};
constexpr std::string_view kDeviceKeys[] = {"backend", "max_force_n",
                                            "max_stiffness_n_per_mm"};
constexpr std::string_view kBackends[] = {"mouse", "hid", "falcon",
                                          "simulated"};
constexpr std::string_view kResponseBoxKeys[] = {
    "vendor_id", "product_id", "serial", "button_offset", "buttons"};
constexpr std::string_view kScreenKeys[] = {"width", "height", "fullscreen"};

}  // namespace

bool LooksLikeStationFile(std::string_view text) {
  return text.find("\"burrlab-station/") != std::string_view::npos;
}

StationParseOutcome ParseStation(std::string_view path, std::string_view text) {
  StationParseOutcome outcome;
  std::vector<Diagnostic>& d = outcome.diagnostics;
  std::optional<toml::table> document = ReadStationToml(
      path, text, "station file", kStationFormat, kStationKeys, &d);
  if (!document.has_value()) return outcome;
  const toml::table& root = *document;
  const stimuli::TomlFields fields = StationFields(&d);
  StationConfig config;
  if (const toml::table* t = fields.Table(root, "device", "device")) {
    fields.CheckKeys(*t, "[device]", kDeviceKeys);
    if (auto backend =
            fields.Choice(*t, "backend", "device.backend", kBackends)) {
      config.device = kBackends[static_cast<std::size_t>(*backend)];
    }
    if (auto v = fields.PositiveNumberUpTo(*t, "max_force_n",
                                           "device.max_force_n", 20.0)) {
      config.max_force_n = *v;
    }
    if (auto v =
            fields.PositiveNumberUpTo(*t, "max_stiffness_n_per_mm",
                                      "device.max_stiffness_n_per_mm", 50.0)) {
      config.max_stiffness_n_per_mm = *v;
    }
  }
  if (const toml::table* t =
          fields.Table(root, "response_box", "response_box")) {
    fields.CheckKeys(*t, "[response_box]", kResponseBoxKeys);
    HidBoxOptions box;
    bool ok = true;
    for (auto [key, field] : {std::pair{"vendor_id", &box.vendor_id},
                              std::pair{"product_id", &box.product_id}}) {
      if (t->get(key) == nullptr) {
        fields.Fail(*t, fmt::format("[response_box] needs {}", key));
        ok = false;
      } else if (auto v = fields.IntegerIn(
                     *t, key, fmt::format("response_box.{}", key), 1, 0xffff)) {
        *field = static_cast<std::uint16_t>(*v);
      } else {
        ok = false;
      }
    }
    if (t->get("serial") != nullptr) {
      if (auto serial = fields.String(*t, "serial", "response_box.serial")) {
        box.serial = *serial;
      } else {
        ok = false;
      }
    }
    if (auto v = fields.IntegerIn(*t, "button_offset",
                                  "response_box.button_offset", 0, 63)) {
      box.button_offset = static_cast<int>(*v);
    }
    const toml::node* buttons = t->get("buttons");
    const toml::table* bt = buttons ? buttons->as_table() : nullptr;
    if (buttons == nullptr) {
      fields.Fail(*t,
                  "[response_box] needs buttons, e.g. buttons = { 1 = "
                  "\"1\", 2 = \"2\" }");
      ok = false;
    } else if (bt == nullptr || bt->empty()) {
      fields.Fail(*buttons,
                  "buttons must map button numbers to keys, e.g. { 1 = "
                  "\"1\" }");
      ok = false;
    } else {
      for (const auto& [key, value] : *bt) {
        int number = 0;
        const std::string k(key.str());
        const bool digits =
            !k.empty() && k.size() <= 3 &&
            k.find_first_not_of("0123456789") == std::string::npos;
        if (digits) number = std::stoi(k);
        if (!digits || number < 1 || number > 512) {
          fields.Fail(key.source().begin,
                      fmt::format("button \"{}\" must be a number from 1 to "
                                  "512",
                                  stimuli::EchoText(k)));
          ok = false;
          continue;
        }
        const std::optional<std::string> name = value.value<std::string>();
        if (!value.is_string() || !name.has_value() || name->empty() ||
            name->size() > 16) {
          fields.Fail(value, fmt::format("button {} must map to a key name "
                                         "of 1 to 16 characters",
                                         number));
          ok = false;
          continue;
        }
        box.buttons.push_back({number, *name});
      }
    }
    if (ok) config.response_box = box;
  }
  if (const toml::table* t = fields.Table(root, "screen", "screen")) {
    fields.CheckKeys(*t, "[screen]", kScreenKeys);
    if (auto v = fields.IntegerIn(*t, "width", "screen.width", 320, 8192)) {
      config.screen_width = static_cast<int>(*v);
    }
    if (auto v = fields.IntegerIn(*t, "height", "screen.height", 240, 8192)) {
      config.screen_height = static_cast<int>(*v);
    }
    if (auto v = fields.Boolean(*t, "fullscreen", "screen.fullscreen")) {
      config.fullscreen = *v;
    }
  }
  if (config.device == "hid" && !config.response_box.has_value() &&
      root.get("response_box") == nullptr) {
    const toml::node* n = root.get("device");
    d.push_back({n != nullptr ? At(*n) : SourceLocation{1, 1},
                 "backend \"hid\" needs a [response_box] table"});
  }
  if (d.empty()) outcome.station = config;
  return outcome;
}

}  // namespace burrlab::runner
