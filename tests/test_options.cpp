// Declared options (core/options.h): values parsed into their members, refused with the option's
// name, nested structs reached through their member, metrics.json keys.
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "core/options.h"
#include "render_fixture.h"

namespace penumbra::test {
namespace {

struct Inner {
  float width = 1.0f;
  bool on = false;
  std::uint32_t maps = 1;
};
struct Outer {
  Inner inner;
  bool thin = true;
};

Options<Inner> innerOptions() {
  Options<Inner> o("Inner");
  o.number("--width", "inner/width", &Inner::width, "width", 0.0f, 8.0f);
  o.choice("--on", "inner/on", &Inner::on, "on or off", {{"on", true}, {"off", false}});
  o.choice("--maps", "inner/maps", &Inner::maps, "1 or 5", {{"1", 1u}, {"5", 5u}});
  return o;
}

const Option<Outer>& find(const Options<Outer>& options, const std::string& name) {
  for (const Option<Outer>& o : options.all()) {
    if (o.name == name) return o;
  }
  throw std::runtime_error("no option " + name);
}

TEST(Options, SetTheirMembersAndRefuseWhatTheyDoNotTake) {
  Options<Outer> options("Outer");
  options.add(&Outer::inner, innerOptions());
  options.flag("--no-thin", "thin", &Outer::thin, "no thin pass", false);
  Outer s;
  find(options, "--width").set(s, "2.5");
  find(options, "--on").set(s, "on");
  find(options, "--maps").set(s, "5");
  find(options, "--no-thin").set(s, {});
  EXPECT_EQ(s.inner.width, 2.5f);
  EXPECT_TRUE(s.inner.on);
  EXPECT_EQ(s.inner.maps, 5u);
  EXPECT_FALSE(s.thin);
  EXPECT_EQ(find(options, "--width").group, "Inner");
  EXPECT_EQ(find(options, "--no-thin").group, "Outer");
  EXPECT_EQ(find(options, "--on").text(s), "on");

  for (const auto& [name, value] : {std::pair{"--width", "9"}, std::pair{"--width", "-1"}, std::pair{"--width", "nan"},
                                    std::pair{"--width", "2x"}, std::pair{"--on", "maybe"}, std::pair{"--maps", "3"}}) {
    const Outer before = s;
    const std::string message = messageOf([&] { find(options, name).set(s, value); });
    EXPECT_NE(message.find(std::string(name) + " '" + value + "'"), std::string::npos) << message;
    EXPECT_EQ(s.inner.width, before.inner.width) << name << " " << value;
    EXPECT_EQ(s.inner.maps, before.inner.maps) << name << " " << value;
  }
}

TEST(Options, RecordTheirValuesWhereMetricsJsonHoldsThem) {
  Options<Outer> options;
  options.add(&Outer::inner, innerOptions());
  Outer s;
  s.inner.maps = 5;
  nlohmann::json out;
  for (const Option<Outer>& o : options.all()) out[nlohmann::json::json_pointer("/" + o.key)] = o.json(s);
  EXPECT_EQ(out["inner"]["width"], 1.0);
  EXPECT_EQ(out["inner"]["on"], "off");  // a choice: its name
  EXPECT_EQ(out["inner"]["maps"], 5);    // a count: its value
}

// The renderer's declared options: each name once, each with help and a topic, and the defaults
// they show are RenderSettings' own.
TEST(Options, RenderOptionsAreDeclaredOnceWithHelpAndTopic) {
  std::set<std::string> names, keys;
  const RenderSettings defaults;
  for (const Option<RenderSettings>& o : renderOptions().all()) {
    EXPECT_TRUE(names.insert(o.name).second) << o.name << " declared twice";
    EXPECT_TRUE(keys.insert(o.key).second) << o.key << " recorded twice";
    EXPECT_FALSE(o.help.empty()) << o.name;
    EXPECT_FALSE(o.group.empty()) << o.name;
    RenderSettings s = defaults;
    if (!o.flag) o.set(s, o.text(defaults));  // the default reads back as itself
    EXPECT_EQ(o.text(s), o.text(defaults)) << o.name;
  }
  EXPECT_TRUE(names.count("--ray-intervals") && names.count("--shadow-map-res") && names.count("--srt-choice"));
}

}  // namespace
}  // namespace penumbra::test
