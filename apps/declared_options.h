// Declared options (core/options.h) on the command line and in metrics.json: each becomes a CLI11
// option in its topic's --help group, writing straight into the settings it belongs to.
#pragma once
#include <algorithm>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

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
      cli->type_name(o.value);
    }
    cli->group(o.group);
  }
}

// Writes each option's value into `out` at its key ("pip/delta": out["pip"]["delta"]).
template <class S>
void recordDeclaredOptions(nlohmann::json& out, const S& settings, const Options<S>& options) {
  for (const Option<S>& o : options.all()) out[nlohmann::json::json_pointer("/" + o.key)] = o.json(settings);
}

// Every option as Markdown, a table per topic in declaration order: name, what it takes, the
// default `settings` holds, its metrics.json key, which methods `bench` re-runs when it sweeps the
// option, and the help (docs/options.md is `penumbra options`' output).
template <class S>
std::string declaredOptionsMarkdown(const Options<S>& options, const S& settings) {
  const auto cell = [](std::string text) {
    for (std::size_t at = 0; (at = text.find('|', at)) != std::string::npos; at += 2) text.insert(at, "\\");
    return text;
  };
  std::vector<std::string> groups;
  for (const Option<S>& o : options.all()) {
    if (std::find(groups.begin(), groups.end(), o.group) == groups.end()) groups.push_back(o.group);
  }
  std::ostringstream out;
  for (const std::string& group : groups) {
    out << "\n## " << group << "\n\n| Option | Takes | Default | metrics.json | bench sweeps | What it does |\n"
        << "|---|---|---|---|---|---|\n";
    for (const Option<S>& o : options.all()) {
      if (o.group != group) continue;
      std::string names, sweeps;
      for (std::size_t at = 0; at <= o.name.size();) {
        const std::size_t end = std::min(o.name.find(',', at), o.name.size());
        names += (names.empty() ? "`" : ", `") + o.name.substr(at, end - at) + "`";
        at = end + 1;
      }
      if (o.sweep) {
        for (const std::string& m : o.sweep->methods) sweeps += (sweeps.empty() ? "" : ", ") + m;
      }
      out << "| " << names << " | " << cell(o.flag ? "(flag)" : o.value) << " | "
          << cell(o.flag ? "not given" : "`" + o.text(settings) + "`") << " | `" << o.key << "` | " << sweeps << " | "
          << cell(o.help) << " |\n";
    }
  }
  return out.str();
}

}  // namespace penumbra
