// The parameters a sweep varies (apps/sweep.h): the axes (the declared options that can be swept), a
// parameter's text in chart labels, and run options applied through the parser `render` uses.
#include <algorithm>
#include <charconv>

#include "apps/sweep.h"
#include "hybrid/render_settings.h"

namespace penumbra {

const std::vector<AxisDef>& sweepAxes() {
  static const std::vector<AxisDef> axes = [] {
    std::vector<AxisDef> a{
        {"--tracer",
         "--tracer",
         {"", {"srt", "frt", "ao", "indirect"}},
         "Ray tracers of srt and frt, e.g. bvh,rq,embree; of ao and indirect, e.g. bvh,bvh-ls,ntree-ls"}};
    for (const Option<RenderSettings>& o : renderOptions().all()) {
      if (!o.sweep) continue;
      const std::string name = o.name.substr(0, o.name.find(','));
      std::string methods;
      for (const std::string& m : o.sweep->methods) methods += (methods.empty() ? "" : ", ") + m;
      a.push_back({o.sweep->alias.empty() ? name : o.sweep->alias + "," + name, name, *o.sweep,
                   "Values of " + name + ", comma-separated (" + methods + "): " + o.help});
    }
    return a;
  }();
  return axes;
}

namespace {

std::string shortName(const std::string& option) {
  for (const AxisDef& axis : sweepAxes()) {
    if (option == axis.option) return axis.axis.shortName;
  }
  return option.substr(option.find_first_not_of('-'));
}

}  // namespace

std::string shortNumber(float value) {
  char text[32];
  const auto [end, ec] = std::to_chars(text, text + sizeof(text), value);
  return ec == std::errc() ? std::string(text, end) : std::to_string(value);
}

std::string paramText(const std::string& option, const std::string& value) {
  const std::string name = shortName(option);
  return name.empty() ? value : name + "=" + value;
}

const std::string* findParam(const RunOptions& params, const std::string& option) {
  for (const auto& [name, value] : params) {
    if (name == option) return &value;
  }
  return nullptr;
}

void applyRunOptions(RunConfig& config, const RunOptions& options) {
  if (options.empty()) return;
  CLI::App parser{"sweep configuration"};
  addRunOptions(parser, config);
  std::vector<std::string> args;
  for (const auto& [option, value] : options) {
    if (!parser.get_option_no_throw(option)) {
      throw InputError(option + " is not an option of this build's renderer, so it cannot be swept (see render --help)");
    }
    args.push_back(option);
    args.push_back(value);
  }
  std::reverse(args.begin(), args.end());  // CLI11 takes the arguments last first
  try {
    parser.parse(args);
  } catch (const CLI::ParseError& e) {
    throw InputError(std::string(e.what()));
  }
}

}  // namespace penumbra
