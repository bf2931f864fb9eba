// station.toml parsing and checking.
#include "station/station_file.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>
#include <set>

#include "burrlab/base/printable.h"
#include "station/station_toml.h"

namespace burrlab::runner {
namespace {

using protocols::Diagnostic;
using protocols::SourceLocation;

}  // namespace

bool LooksLikeStationFile(std::string_view text) {
  return text.find("\"burrlab-station/") != std::string_view::npos;
}

StationParseOutcome ParseStation(std::string_view path, std::string_view text) {
  StationParseOutcome outcome;
  std::vector<Diagnostic>& d = outcome.diagnostics;
  std::optional<toml::table> document =
      ReadStationToml(path, text, "station file", kStationFormat,
                      {"format", "device", "response_box", "screen"}, &d);
  if (!document.has_value()) return outcome;
  const toml::table& root = *document;
  const auto report = [&d](const toml::node& n, std::string message) {
    d.push_back({At(n), std::move(message)});
  };
  const auto only_keys = [&d](const toml::table& t, std::string_view where,
                              const std::set<std::string_view>& known) {
    OnlyKeys(t, where, known, &d);
  };
  const auto integer = [&d](const toml::table& t, std::string_view key,
                            std::string_view name, std::int64_t lo,
                            std::int64_t hi) {
    return Integer(t, key, name, lo, hi, &d);
  };
  StationConfig config;
  if (const toml::node* n = root.get("device")) {
    const toml::table* t = n->as_table();
    if (t == nullptr) {
      report(*n, "[device] must be a table");
    } else {
      only_keys(*t, "[device]",
                {"backend", "max_force_n", "max_stiffness_n_per_mm"});
      if (const toml::node* b = t->get("backend")) {
        const std::optional<std::string> name = b->value<std::string>();
        if (!name.has_value() || !b->is_string() ||
            (*name != "mouse" && *name != "hid" && *name != "falcon" &&
             *name != "simulated")) {
          report(*b,
                 "backend must be one of \"mouse\", \"hid\", \"falcon\", "
                 "\"simulated\"");
        } else {
          config.device = *name;
        }
      }
      if (const toml::node* f = t->get("max_force_n")) {
        const std::optional<double> v = f->value<double>();
        if (!v.has_value() || !std::isfinite(*v) || *v <= 0.0 || *v > 20.0) {
          report(*f, "max_force_n must be a number of newtons in (0, 20]");
        } else {
          config.max_force_n = *v;
        }
      }
      if (const toml::node* k = t->get("max_stiffness_n_per_mm")) {
        const std::optional<double> v = k->value<double>();
        if (!v.has_value() || !std::isfinite(*v) || *v <= 0.0 || *v > 50.0) {
          report(*k,
                 "max_stiffness_n_per_mm must be a number of N/mm in (0, "
                 "50]");
        } else {
          config.max_stiffness_n_per_mm = *v;
        }
      }
    }
  }
  if (const toml::node* n = root.get("response_box")) {
    const toml::table* t = n->as_table();
    if (t == nullptr) {
      report(*n, "[response_box] must be a table");
    } else {
      only_keys(
          *t, "[response_box]",
          {"vendor_id", "product_id", "serial", "button_offset", "buttons"});
      HidBoxOptions box;
      bool ok = true;
      for (auto [key, field] : {std::pair{"vendor_id", &box.vendor_id},
                                std::pair{"product_id", &box.product_id}}) {
        if (t->get(key) == nullptr) {
          report(*n, fmt::format("[response_box] needs {}", key));
          ok = false;
        } else if (auto v = integer(*t, key, key, 1, 0xffff)) {
          *field = static_cast<std::uint16_t>(*v);
        } else {
          ok = false;
        }
      }
      if (const toml::node* s = t->get("serial")) {
        if (!s->is_string()) {
          report(*s, "serial must be a string");
          ok = false;
        } else {
          box.serial = *s->value<std::string>();
        }
      }
      if (auto v = integer(*t, "button_offset", "button_offset", 0, 63)) {
        box.button_offset = static_cast<int>(*v);
      }
      const toml::node* buttons = t->get("buttons");
      const toml::table* bt = buttons ? buttons->as_table() : nullptr;
      if (buttons == nullptr) {
        report(*n,
               "[response_box] needs buttons, e.g. buttons = { 1 = "
               "\"1\", 2 = \"2\" }");
        ok = false;
      } else if (bt == nullptr || bt->empty()) {
        report(*buttons,
               "buttons must map button numbers to keys, e.g. { 1 = \"1\" }");
        ok = false;
      } else {
        for (const auto& [key, value] : *bt) {
          int number = 0;
          const std::string k(key.str());
          const bool digits =
              !k.empty() && k.size() <= 3 &&
              k.find_first_not_of("0123456789") == std::string::npos;
          if (digits) number = std::stoi(k);
          const SourceLocation where{
              static_cast<int>(key.source().begin.line),
              static_cast<int>(key.source().begin.column)};
          if (!digits || number < 1 || number > 512) {
            d.push_back({where, fmt::format("button '{}' must be a number "
                                            "from 1 to 512",
                                            PrintableText(k))});
            ok = false;
            continue;
          }
          const std::optional<std::string> name = value.value<std::string>();
          if (!value.is_string() || !name.has_value() || name->empty() ||
              name->size() > 16) {
            report(value, fmt::format("button {} must map to a key name of "
                                      "1 to 16 characters",
                                      number));
            ok = false;
            continue;
          }
          box.buttons.push_back({number, *name});
        }
      }
      if (ok) config.response_box = box;
    }
  }
  if (const toml::node* n = root.get("screen")) {
    const toml::table* t = n->as_table();
    if (t == nullptr) {
      report(*n, "[screen] must be a table");
    } else {
      only_keys(*t, "[screen]", {"width", "height", "fullscreen"});
      if (auto v = integer(*t, "width", "width", 320, 8192)) {
        config.screen_width = static_cast<int>(*v);
      }
      if (auto v = integer(*t, "height", "height", 240, 8192)) {
        config.screen_height = static_cast<int>(*v);
      }
      if (const toml::node* f = t->get("fullscreen")) {
        if (!f->is_boolean()) {
          report(*f, "fullscreen must be true or false");
        } else {
          config.fullscreen = *f->value<bool>();
        }
      }
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
