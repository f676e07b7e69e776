// The documentation holds together: the README stays whole where users read it (GitHub shows a
// README on a repository's front page only up to its first 512,000 bytes), every link between
// README.md and tests/RESULTS.md finds its file and section, and every section that code and
// configuration comments cite by title ('README "Clocks"', 'tests/RESULTS.md "Tried last"')
// exists. Section anchors are made as GitHub makes them (lower case, punctuation dropped,
// spaces to hyphens, a repeated heading numbered -1, -2, ...).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kRoot = LASONIC_SOURCE_DIR;
constexpr std::size_t kFrontPageBytes = 512000;

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// One UTF-8 code point from s at i (advances i); malformed bytes are taken one by one.
std::uint32_t nextCodePoint(const std::string& s, std::size_t& i) {
  const auto b = static_cast<unsigned char>(s[i]);
  int n = b < 0x80 ? 0 : (b >> 5) == 0x6 ? 1 : (b >> 4) == 0xE ? 2 : (b >> 3) == 0x1E ? 3 : 0;
  if (i + n >= s.size()) n = 0;
  std::uint32_t cp = n == 0 ? b : n == 1 ? (b & 0x1F) : n == 2 ? (b & 0x0F) : (b & 0x07);
  for (int k = 1; k <= n; ++k) cp = (cp << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
  i += n + 1;
  return cp;
}

void appendUtf8(std::string& out, std::uint32_t cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

// A heading's anchor as GitHub makes it. Letters and digits stay (Latin, Greek and Cyrillic
// letters beyond ASCII too, lower-cased where Latin-1 has the pair), '-' and '_' stay, a space
// becomes '-', everything else (punctuation, dashes, symbols such as ≤ and →) is dropped.
std::string anchorOf(const std::string& heading) {
  std::string out;
  for (std::size_t i = 0; i < heading.size();) {
    std::uint32_t cp = nextCodePoint(heading, i);
    if (cp < 0x80) {
      const char c = static_cast<char>(cp);
      if (c >= 'A' && c <= 'Z') out += static_cast<char>(c - 'A' + 'a');
      else if ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_') out += c;
      else if (c == ' ') out += '-';
      continue;
    }
    const bool latin = cp >= 0xC0 && cp <= 0x24F && cp != 0xD7 && cp != 0xF7;
    const bool greek = cp >= 0x386 && cp <= 0x3FF && cp != 0x387;
    const bool cyrillic = cp >= 0x400 && cp <= 0x4FF;
    if (!(latin || greek || cyrillic)) continue;
    if (cp >= 0xC0 && cp <= 0xDE) cp += 0x20;  // Latin-1 upper case to lower case
    appendUtf8(out, cp);
  }
  return out;
}

bool isFence(const std::string& l) { return l.rfind("```", 0) == 0; }

struct Heading {
  std::string text;    // as written, backticks removed
  std::string anchor;  // with GitHub's -1, -2 for a repeated one
};

std::vector<Heading> headingsOf(const std::string& markdown) {
  static const std::regex kHeading(R"(^#{1,6}\s+(.*?)\s*$)");
  std::vector<Heading> out;
  std::map<std::string, int> seen;
  bool fence = false;
  for (const auto& l : lines(markdown)) {
    if (isFence(l)) {
      fence = !fence;
      continue;
    }
    std::smatch m;
    if (fence || !std::regex_match(l, m, kHeading)) continue;
    std::string text = m[1].str();
    text.erase(std::remove(text.begin(), text.end(), '`'), text.end());
    std::string anchor = anchorOf(m[1].str());
    auto [it, fresh] = seen.emplace(anchor, 0);
    if (!fresh) anchor += "-" + std::to_string(++it->second);
    out.push_back({text, anchor});
  }
  return out;
}

struct Link {
  int line;
  std::string target;
};

// Markdown link targets outside fenced code and inline code spans.
std::vector<Link> linksOf(const std::string& markdown) {
  static const std::regex kCode("`[^`]*`");
  static const std::regex kLink(R"(\]\(([^)\s]+)\))");
  std::vector<Link> out;
  bool fence = false;
  int n = 0;
  for (const auto& l : lines(markdown)) {
    ++n;
    if (isFence(l)) {
      fence = !fence;
      continue;
    }
    if (fence) continue;
    const std::string prose = std::regex_replace(l, kCode, "");
    for (std::sregex_iterator it(prose.begin(), prose.end(), kLink), end; it != end; ++it)
      out.push_back({n, (*it)[1].str()});
  }
  return out;
}

bool external(const std::string& target) {
  return target.rfind("http://", 0) == 0 || target.rfind("https://", 0) == 0 ||
         target.rfind("mailto:", 0) == 0;
}

// Every relative link of `doc` that does not find its file, or its section in that file.
std::vector<std::string> brokenLinks(const fs::path& doc, const std::string& text,
                                     const std::function<std::string(const fs::path&)>& read) {
  std::vector<std::string> broken;
  for (const auto& link : linksOf(text)) {
    if (external(link.target)) continue;
    const auto hash = link.target.find('#');
    const std::string file = link.target.substr(0, hash);
    const fs::path target = file.empty() ? doc : (doc.parent_path() / file).lexically_normal();
    const std::string where = doc.filename().string() + ":" + std::to_string(link.line) + " " +
                              link.target;
    if (!file.empty() && !fs::exists(target)) {
      broken.push_back(where + " (no such file)");
      continue;
    }
    if (hash == std::string::npos) continue;
    const std::string anchor = link.target.substr(hash + 1);
    const auto hs = headingsOf(file.empty() ? text : read(target));
    if (std::none_of(hs.begin(), hs.end(), [&](const Heading& h) { return h.anchor == anchor; }))
      broken.push_back(where + " (no such section)");
  }
  return broken;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += "\n  " + x;
  return s;
}

TEST(Docs, AnchorsAreMadeAsGitHubMakesThem) {
  EXPECT_EQ(anchorOf("Scene suite (`./run score --all`, seeds 1–5, measured 2026-11-30)"),
            "scene-suite-run-score---all-seeds-15-measured-2026-11-30");
  EXPECT_EQ(anchorOf("Complement extraction, ideal profile (targets: `invisible_recall` ≥ 0.90)"),
            "complement-extraction-ideal-profile-targets-invisible_recall--090");
  EXPECT_EQ(anchorOf("SONAR_TRUTH and LASER_TRUTH: the cause of every reading"),
            "sonar_truth-and-laser_truth-the-cause-of-every-reading");
  EXPECT_EQ(anchorOf("A box's side passed close by is no person"),
            "a-boxs-side-passed-close-by-is-no-person");
  EXPECT_EQ(anchorOf("Jörg's Ö → ok"), "jörgs-ö--ok");
  const auto hs = headingsOf("# A\n## A\n```\n# A\n```\n### A\n");
  ASSERT_EQ(hs.size(), 3u);
  EXPECT_EQ(hs[0].anchor, "a");
  EXPECT_EQ(hs[1].anchor, "a-1");
  EXPECT_EQ(hs[2].anchor, "a-2");
}

TEST(Docs, ABrokenLinkIsFound) {
  const fs::path doc = kRoot / "README.md";
  const std::string text =
      "# Top\n## Part two\n[ok](#part-two) [ok](tests/RESULTS.md) `[code](#nowhere)`\n"
      "[gone](#part-three) [gone](no/such.md) [gone](tests/RESULTS.md#no-such-section)\n"
      "```\n[fenced](#nowhere)\n```\n[web](https://lcm-proj.github.io/)\n";
  const auto broken =
      brokenLinks(doc, text, [](const fs::path& p) { return readFile(p); });
  ASSERT_EQ(broken.size(), 3u) << joined(broken);
  EXPECT_NE(broken[0].find("#part-three (no such section)"), std::string::npos);
  EXPECT_NE(broken[1].find("no/such.md (no such file)"), std::string::npos);
  EXPECT_NE(broken[2].find("#no-such-section (no such section)"), std::string::npos);
}

TEST(Docs, TheReadmeFitsOnARepositoryFrontPage) {
  const auto bytes = fs::file_size(kRoot / "README.md");
  EXPECT_LT(bytes, kFrontPageBytes)
      << "README.md is " << bytes << " bytes: GitHub cuts a README off after " << kFrontPageBytes
      << " on the front page; move measurement history to tests/RESULTS.md";
}

TEST(Docs, EveryLinkFindsItsFileAndSection) {
  for (const char* name : {"README.md", "tests/RESULTS.md"}) {
    const fs::path doc = kRoot / name;
    ASSERT_TRUE(fs::exists(doc)) << doc;
    const auto broken =
        brokenLinks(doc, readFile(doc), [](const fs::path& p) { return readFile(p); });
    EXPECT_TRUE(broken.empty()) << name << ":" << joined(broken);
    EXPECT_GT(linksOf(readFile(doc)).size(), 10u) << name;  // the parser found the links at all
  }
}

TEST(Docs, EverySectionCitedInTheCodeExists) {
  // A citation names a section's title or its start: README "Method", step 4 is the section
  // "Method, as implemented". Only citations whose title is on one line are checked.
  static const std::regex kCite(R"re((README|tests/RESULTS\.md)(?:'s|,)?\s*\(?\\?"([A-Za-z][^"\n\\]*)\\?")re");
  std::map<std::string, std::vector<Heading>> heads = {
      {"README", headingsOf(readFile(kRoot / "README.md"))},
      {"tests/RESULTS.md", headingsOf(readFile(kRoot / "tests/RESULTS.md"))}};
  const std::set<std::string> exts = {".cpp", ".hpp", ".h",    ".sh",  ".yaml",
                                      ".cmake", ".txt", ".java", ".lcm", ".py"};
  std::vector<fs::path> files = {kRoot / "run", kRoot / ".ci/run", kRoot / "CMakeLists.txt"};
  for (const char* dir : {"common", "procs", "tests", "deploy", "lcmtypes"})
    for (const auto& e : fs::recursive_directory_iterator(kRoot / dir))
      if (e.is_regular_file() && exts.count(e.path().extension().string()))
        files.push_back(e.path());
  std::vector<std::string> missing;
  int cited = 0;
  for (const auto& f : files) {
    const std::string text = readFile(f);
    for (std::sregex_iterator it(text.begin(), text.end(), kCite), end; it != end; ++it) {
      ++cited;
      const std::string doc = (*it)[1].str(), title = (*it)[2].str();
      const auto& hs = heads.at(doc);
      if (std::none_of(hs.begin(), hs.end(),
                       [&](const Heading& h) { return h.text.rfind(title, 0) == 0; }))
        missing.push_back(fs::relative(f, kRoot).string() + ": " + doc + " \"" + title + "\"");
    }
  }
  EXPECT_GT(cited, 100);  // the scan found the code's citations at all
  EXPECT_TRUE(missing.empty()) << "cited sections that do not exist:" << joined(missing);
}

}  // namespace
