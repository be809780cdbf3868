// README.md and docs/*.md: every relative link and image resolves to a file or folder of the source
// tree and stays inside it, and the README stays a short front door that links every docs page.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace penumbra::test {
namespace {

namespace fs = std::filesystem;

fs::path sourceDir() { return fs::weakly_canonical(fs::path(PENUMBRA_SOURCE_DIR)); }

// README.md and every docs/*.md, sorted.
std::vector<fs::path> pages() {
  std::vector<fs::path> result{sourceDir() / "README.md"};
  std::vector<fs::path> docs;
  for (const fs::directory_entry& entry : fs::directory_iterator(sourceDir() / "docs")) {
    if (entry.is_regular_file() && entry.path().extension() == ".md") docs.push_back(entry.path());
  }
  std::sort(docs.begin(), docs.end());
  result.insert(result.end(), docs.begin(), docs.end());
  return result;
}

struct Link {
  int line;
  std::string target;  // as written, without its #anchor and "title"
};

// Every `](target)` of a markdown file: links and images. Web links, mail links and links to an
// anchor of the same page are left out.
std::vector<Link> links(const fs::path& file) {
  std::vector<Link> result;
  std::ifstream in(file);
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    for (std::size_t at = line.find("]("); at != std::string::npos; at = line.find("](", at + 2)) {
      const std::size_t end = line.find(')', at + 2);
      if (end == std::string::npos) continue;
      std::string target = line.substr(at + 2, end - at - 2);
      const std::size_t title = target.find(" \"");
      if (title != std::string::npos) target.erase(title);
      if (target.size() >= 2 && target.front() == '<' && target.back() == '>') target = target.substr(1, target.size() - 2);
      if (target.empty() || target.front() == '#') continue;
      if (target.rfind("http:", 0) == 0 || target.rfind("https:", 0) == 0 || target.rfind("mailto:", 0) == 0) continue;
      const std::size_t anchor = target.find('#');
      if (anchor != std::string::npos) target.erase(anchor);
      result.push_back({number, target});
    }
  }
  return result;
}

bool inside(const fs::path& path, const fs::path& root) {
  const std::string p = path.lexically_normal().generic_string();
  std::string r = root.lexically_normal().generic_string();
  if (!r.empty() && r.back() == '/') r.pop_back();
  return p == r || p.rfind(r + "/", 0) == 0;
}

TEST(DocsLinks, EveryLinkInTheReadmeAndDocsResolves) {
  const fs::path root = sourceDir();
  ASSERT_TRUE(fs::exists(root / "README.md")) << "README.md not found in " << root;
  ASSERT_TRUE(fs::is_directory(root / "docs")) << "docs/ not found in " << root;
  int checked = 0;
  for (const fs::path& page : pages()) {
    const std::string name = page.lexically_relative(root).generic_string();
    for (const Link& link : links(page)) {
      ++checked;
      const fs::path resolved = fs::weakly_canonical(page.parent_path() / link.target);
      EXPECT_TRUE(fs::exists(resolved)) << name << ":" << link.line << ": link target '" << link.target
                                        << "' does not exist (" << resolved.generic_string() << ")";
      EXPECT_TRUE(inside(resolved, root)) << name << ":" << link.line << ": link target '" << link.target
                                          << "' points outside the repository (" << resolved.generic_string() << ")";
    }
  }
  EXPECT_GT(checked, 0) << "no links found: the parser is broken";
}

TEST(DocsLinks, ReadmeIsAFrontDoor) {
  const fs::path root = sourceDir();
  const fs::path readme = root / "README.md";
  ASSERT_TRUE(fs::exists(readme));
  EXPECT_LE(fs::file_size(readme), 12u * 1024u) << "README.md should stay a short front door: move reference text into docs/";
  std::vector<fs::path> linked;
  for (const Link& link : links(readme)) linked.push_back(fs::weakly_canonical(root / link.target));
  for (const fs::path& page : pages()) {
    if (page.filename() == "README.md" && page.parent_path() == root) continue;
    const fs::path canonical = fs::weakly_canonical(page);
    EXPECT_NE(std::find(linked.begin(), linked.end(), canonical), linked.end())
        << "README.md does not link " << page.lexically_relative(root).generic_string();
  }
}

// The link parser itself, on a file whose links are known.
TEST(DocsLinks, LinksAreFoundAsWritten) {
  const fs::path file = fs::temp_directory_path() / "penumbra_docs_links_test.md";
  {
    std::ofstream out(file);
    out << "# t\n"
        << "see [a](docs/a.md#part) and ![img](images/x.png \"a title\")\n"
        << "[web](https://example.com) [mail](mailto:x@y.z) [here](#top) [plain http](http://x)\n"
        << "[folder](../core/) [angle](<b.md>)\n";
  }
  const std::vector<Link> found = links(file);
  fs::remove(file);
  ASSERT_EQ(found.size(), 4u);
  EXPECT_EQ(found[0].target, "docs/a.md");
  EXPECT_EQ(found[0].line, 2);
  EXPECT_EQ(found[1].target, "images/x.png");
  EXPECT_EQ(found[2].target, "../core/");
  EXPECT_EQ(found[2].line, 4);
  EXPECT_EQ(found[3].target, "b.md");
  EXPECT_TRUE(inside(fs::path("/a/b/c"), fs::path("/a/b")));
  EXPECT_FALSE(inside(fs::path("/a/bc"), fs::path("/a/b")));
  EXPECT_FALSE(inside(fs::path("/a"), fs::path("/a/b")));
}

}  // namespace
}  // namespace penumbra::test
