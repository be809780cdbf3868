// The parameters a sweep varies (apps/sweep.h): the axes and the methods each one changes, a
// parameter's text in chart labels, and run options applied through the parser `render` uses.
#include <algorithm>
#include <charconv>

#include "apps/sweep.h"

namespace penumbra {

const std::vector<AxisDef>& sweepAxes() {
  static const std::vector<AxisDef> axes{
      {"--sm-res,--shadow-map-res", "--shadow-map-res", "res", {"sm", "pcf", "pcss", "msm", "srt"}, false, false,
       "Shadow-map resolutions, e.g. 1024,2048 (sm, pcf, pcss, msm, srt)"},
      {"--pcf-kernel", "--pcf-kernel", "", {"pcf"}, false, false, "PCF kernels, e.g. 3x3,5x5,poisson (pcf)"},
      {"--pip-delta", "--pip-delta", "delta", {"srt"}, false, false, "PIP depth-edge thresholds, e.g. 0.001,0.002 (srt)"},
      {"--pip-margin", "--pip-margin", "margin", {"srt"}, false, false, "PIP receiver margins in texels (srt)"},
      {"--msm-maps", "--msm-maps", "K", {"msm"}, false, false, "Maps averaged by msm, e.g. 4,16"},
      {"--penumbra-maps", "--penumbra-maps", "pmaps", {"srt"}, true, false,
       "Maps of srt's penumbra mask with area lights: 1 (centre), 5 (and corners)"},
      {"--spp", "--spp", "spp", {"srt", "frt", "ls", "bitmask"}, true, false,
       "Light samples per pixel with area lights, e.g. 4,16 (srt, frt, ls, bitmask)"},
      {"--tracer", "--tracer", "", {"srt", "frt", "ao", "indirect"}, false, false,
       "Ray tracers of srt and frt, e.g. bvh,rq,embree; of ao and indirect, e.g. bvh,bvh-ls,ntree-ls"},
      {"--denoise", "--denoise", "denoise", {"srt", "frt"}, true, false,
       "Shadow denoiser of srt and frt with area lights, e.g. off,temporal"},
      {"--linespace-n", "--linespace-n", "N", {"srt", "frt", "ls"}, false, true,
       "Line-space subdivision N per level (with the line-space tracer), e.g. 4,6,8"},
      {"--linespace-depth", "--linespace-depth", "d", {"srt", "frt", "ls"}, false, true,
       "Line-space tree depth d (with the line-space tracer), e.g. 2,3"},
      {"--bitmask-samples", "--bitmask-samples", "samples", {"bitmask"}, false, false,
       "Bitmask visibility samples (method bitmask)"},
  };
  return axes;
}

namespace {

std::string shortName(const std::string& option) {
  for (const AxisDef& axis : sweepAxes()) {
    if (option == axis.option) return axis.shortName;
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
