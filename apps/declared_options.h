// Declared options (core/options.h) on the command line and in metrics.json: each becomes a CLI11
// option in its topic's --help group, writing straight into the settings it belongs to.
#pragma once
#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "core/options.h"

namespace penumbra {

// Adds `options` to `app`, each setting its member of `settings` when given; --help shows the value
// `settings` holds now as the default.
template <class S>
void addDeclaredOptions(CLI::App& app, S& settings, const Options<S>& options) {
  for (const Option<S>& o : options.all()) {
    // A refused value is the parser's error, as CLI11's own checks are.
    const auto set = [&settings, set = o.set](const std::string& value) {
      try {
        set(settings, value);
      } catch (const InputError& e) {
        throw CLI::ValidationError(e.what());
      }
    };
    CLI::Option* cli = nullptr;
    if (o.flag) {
      cli = app.add_flag_function(o.name, [set](std::int64_t) { set({}); }, o.help);
    } else {
      cli = app.add_option(o.name, [set](const CLI::results_t& values) { return set(values.back()), true; }, o.help);
      cli->default_str(o.text(settings));
      std::string choices;
      for (const std::string& c : o.choices) choices += (choices.empty() ? "{" : ",") + c;
      cli->type_name(choices.empty() ? "NUMBER" : choices + "}");
    }
    cli->group(o.group);
  }
}

// Writes each option's value into `out` at its key ("pip/delta": out["pip"]["delta"]).
template <class S>
void recordDeclaredOptions(nlohmann::json& out, const S& settings, const Options<S>& options) {
  for (const Option<S>& o : options.all()) out[nlohmann::json::json_pointer("/" + o.key)] = o.json(settings);
}

}  // namespace penumbra
