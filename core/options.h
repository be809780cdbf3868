// Options declared once, beside the settings they set: a pass's, method's or tracer's settings
// struct lists its options (name, topic, help, range or choices, where metrics.json records it),
// and the command line, its --help, metrics.json and the sweep read them from that list
// (apps/declared_options.h, apps/sweep_params.cpp). The default is the struct's own member
// initialiser. An option `bench` may sweep says so after its declaration:
//   o.number("--pip-delta", ...).sweep("delta", {"srt"});
//   Options<PipSettings> o("Selective ray tracing (srt)");
//   o.choice("--ray-intervals", "pip/ray_intervals", &PipSettings::rayIntervals,
//            "Bound srt's hard-shadow rays by the shadow map's blocker depths", {{"on", true}, {"off", false}});
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/scene.h"  // InputError

namespace penumbra {

// How `bench` sweeps an option: a comma-separated list of values, each re-running only `methods`.
struct SweepAxis {
  std::string shortName;             // in chart labels: "res=1024" ("": the bare value)
  std::vector<std::string> methods;  // the methods the option changes
  bool areaLightOnly = false;        // meaningless for a point light (samples per pixel)
  bool lineSpaceOnly = false;        // only with the line-space tracer (method ls, or --tracer ls)
  std::string alias;                 // a shorter name of bench's list ("--sm-res")
};

// One option of settings S, type-erased.
template <class S>
struct Option {
  std::string name;    // "--ray-intervals" (more names: "--ls-shadows,--linespace-shadows", the first one's)
  std::string group;   // the --help topic
  std::string help;
  std::string key;     // where metrics.json's run settings hold it: "pip/ray_intervals"
  std::string value;   // --help's name of what it takes: "NUMBER in 16..16384", "MB", "NAME,..."
  bool flag = false;   // takes no value: given = flagValue
  std::vector<std::string> choices;  // the values it takes, when it is a choice
  std::function<void(S&, const std::string&)> set;  // parses one value (a flag: ignored); InputError if refused
  std::function<std::string(const S&)> text;        // the value as the command line spells it
  std::function<nlohmann::json(const S&)> json;     // ... and as metrics.json records it
  std::optional<SweepAxis> sweep;                   // set: `bench` can sweep it
};

template <class S>
class Options {
 public:
  explicit Options(std::string group = {}) : group_(std::move(group)) {}
  // Later options' topic.
  Options& group(std::string name) {
    group_ = std::move(name);
    return *this;
  }

  // A finite number within [lo, hi].
  template <class T>
  Options& number(std::string name, std::string key, T S::*field, std::string help,
                  T lo = std::numeric_limits<T>::lowest(), T hi = std::numeric_limits<T>::max()) {
    Option<S> o = base(std::move(name), std::move(key), std::move(help));
    std::ostringstream range;
    const bool low = lo != std::numeric_limits<T>::lowest(), high = hi != std::numeric_limits<T>::max();
    if (low && high)
      range << " in " << lo << ".." << hi;
    else if (low)
      range << " >= " << lo;
    else if (high)
      range << " <= " << hi;
    o.value = "NUMBER" + range.str();
    o.set = [field, lo, hi, n = o.name, range = range.str()](S& s, const std::string& text) {
      std::istringstream in(text);
      T value{};
      char extra = 0;
      const bool negativeUnsigned = std::is_unsigned_v<T> && text.find('-') != std::string::npos;  // ">>" wraps it
      if (negativeUnsigned || !(in >> value) || in >> extra || !std::isfinite(double(value)) || value < lo || value > hi) {
        throw InputError(n + " '" + text + "' is not a finite number" + range);
      }
      s.*field = value;
    };
    o.text = [field](const S& s) {
      std::ostringstream out;
      out << s.*field;
      return out.str();
    };
    o.json = [field](const S& s) { return nlohmann::json(s.*field); };
    options_.push_back(std::move(o));
    return *this;
  }

  // One of named values: {{"on", true}, {"off", false}}. metrics.json records the name (a count, its value).
  template <class T>
  Options& choice(std::string name, std::string key, T S::*field, std::string help,
                  std::vector<std::pair<std::string, T>> values) {
    Option<S> o = base(std::move(name), std::move(key), std::move(help));
    for (const auto& [text, value] : values) o.choices.push_back(text);
    for (const std::string& c : o.choices) o.value += (o.value.empty() ? "{" : ",") + c;
    o.value += "}";
    o.set = [field, values, n = o.name, choices = o.choices](S& s, const std::string& text) {
      for (const auto& [t, value] : values) {
        if (t == text) {
          s.*field = value;
          return;
        }
      }
      std::string list;
      for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
      throw InputError(n + " '" + text + "' is not one of " + list);
    };
    o.text = [field, values](const S& s) {
      for (const auto& [t, value] : values) {
        if (value == s.*field) return t;
      }
      return std::string("?");
    };
    bool counts = false;  // names that spell their values: a count (--penumbra-maps 5)
    if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
      counts =
          std::all_of(values.begin(), values.end(), [](const auto& v) { return v.first == std::to_string(v.second); });
    }
    if (counts) {
      o.json = [field](const S& s) { return nlohmann::json(s.*field); };
    } else {
      o.json = [text = o.text](const S& s) { return nlohmann::json(text(s)); };
    }
    options_.push_back(std::move(o));
    return *this;
  }

  // Given without a value, sets the member to `given` (--no-thin: thinPass = false).
  Options& flag(std::string name, std::string key, bool S::*field, std::string help, bool given = true) {
    Option<S> o = base(std::move(name), std::move(key), std::move(help));
    o.flag = true;
    o.set = [field, given](S& s, const std::string&) { s.*field = given; };
    o.text = [field](const S& s) { return std::string(s.*field ? "true" : "false"); };
    o.json = [field](const S& s) { return nlohmann::json(s.*field); };
    options_.push_back(std::move(o));
    return *this;
  }

  // A memory size given in MB (10^6 bytes), >= 0, kept in bytes.
  Options& megabytes(std::string name, std::string key, std::uint64_t S::*field, std::string help) {
    Option<S> o = base(std::move(name), std::move(key), std::move(help));
    o.value = "MB";
    o.set = [field, n = o.name](S& s, const std::string& text) {
      std::istringstream in(text);
      double mb = 0.0;
      char extra = 0;
      if (!(in >> mb) || in >> extra || !std::isfinite(mb) || mb < 0.0 || mb > 1e12) {
        throw InputError(n + " '" + text + "' is not a number of MB >= 0");
      }
      s.*field = std::uint64_t(mb * 1e6);
    };
    o.text = [field](const S& s) {
      std::ostringstream out;
      out << double(s.*field) / 1e6;
      return out.str();
    };
    o.json = [field](const S& s) { return nlohmann::json(double(s.*field) / 1e6); };
    options_.push_back(std::move(o));
    return *this;
  }

  // A comma-separated list of at most `most` names (empty items dropped; none: the empty list).
  Options& list(std::string name, std::string key, std::vector<std::string> S::*field, std::string help,
                std::size_t most = std::numeric_limits<std::size_t>::max()) {
    Option<S> o = base(std::move(name), std::move(key), std::move(help));
    o.value = "NAME,...";
    o.set = [field, most, n = o.name](S& s, const std::string& text) {
      std::vector<std::string> items;
      std::istringstream in(text);
      for (std::string item; std::getline(in, item, ',');) {
        if (!item.empty()) items.push_back(item);
      }
      if (items.size() > most) throw InputError(n + " '" + text + "' names more than " + std::to_string(most));
      s.*field = std::move(items);
    };
    o.text = [field](const S& s) {
      std::string out;
      for (const std::string& item : s.*field) out += (out.empty() ? "" : ",") + item;
      return out;
    };
    o.json = [field](const S& s) { return nlohmann::json(s.*field); };
    options_.push_back(std::move(o));
    return *this;
  }

  // The last declared option can be swept by `bench`.
  Options& sweep(std::string shortName, std::vector<std::string> methods, bool areaLightOnly = false,
                 bool lineSpaceOnly = false, std::string alias = {}) {
    options_.back().sweep =
        SweepAxis{std::move(shortName), std::move(methods), areaLightOnly, lineSpaceOnly, std::move(alias)};
    return *this;
  }

  // Another struct's options, for its member of this struct: RenderSettings holds a PipSettings.
  template <class Inner>
  Options& add(Inner S::*member, const Options<Inner>& inner) {
    for (const Option<Inner>& i : inner.all()) {
      Option<S> o{i.name, i.group, i.help, i.key, i.value, i.flag, i.choices, {}, {}, {}, i.sweep};
      o.set = [member, set = i.set](S& s, const std::string& text) { set(s.*member, text); };
      o.text = [member, text = i.text](const S& s) { return text(s.*member); };
      o.json = [member, json = i.json](const S& s) { return json(s.*member); };
      options_.push_back(std::move(o));
    }
    return *this;
  }

  const std::vector<Option<S>>& all() const { return options_; }

 private:
  Option<S> base(std::string name, std::string key, std::string help) const {
    Option<S> o;
    o.name = std::move(name);
    o.group = group_;
    o.help = std::move(help);
    o.key = std::move(key);
    return o;
  }

  std::string group_;
  std::vector<Option<S>> options_;
};

}  // namespace penumbra
