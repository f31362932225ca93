// index.html of `rayunits report` (issue 17 §4): the converter on a planted page (every
// construct the report writes; a missing image is named), the page of a real small report
// (every image embedded and a PNG, every section anchor present), and — long label, needs
// Debian's chromium (scripts/install-deps.sh --long) — the page opened in headless Chromium:
// the page's own load script reports every image decoded and every section present, read back
// with --dump-dom; a screenshot is kept as a test artifact.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "../common/run_rayunits.hpp"
#include "../common/temp_dir.hpp"
#include "rayunits/report/report.hpp"
#include "rayunits/util/process.hpp"

#include "../common/files.hpp"

namespace {

namespace fs = std::filesystem;

using ru::test::slurp;

struct Dir : ru::test::TempDir {
  Dir() : TempDir("ru_report_html") {}
};

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (auto i = s.find(what); i != std::string::npos; i = s.find(what, i + 1)) ++n;
  return n;
}

// Decodes one base64 string (the test's own decoder, not the converter's encoder).
std::string unbase64(const std::string& s) {
  std::string out;
  int val = 0, bits = -8;
  for (char c : s) {
    int d;
    if (c >= 'A' && c <= 'Z') d = c - 'A';
    else if (c >= 'a' && c <= 'z') d = c - 'a' + 26;
    else if (c >= '0' && c <= '9') d = c - '0' + 52;
    else if (c == '+') d = 62;
    else if (c == '/') d = 63;
    else break;
    val = (val << 6) | d;
    bits += 6;
    if (bits >= 0) {
      out += static_cast<char>((val >> bits) & 0xff);
      bits -= 8;
    }
  }
  return out;
}

TEST(ReportHtml, ConverterOnEveryConstruct) {
  Dir d;
  const std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + "rest of a file";
  {
    std::ofstream f(d.p / "a.png", std::ios::binary);
    f << png;
  }
  const std::string md =
      "# Title <x>\n\n| a | b |\n|---|---:|\n| `c|d` | **2** |\n| 3 | [l](x.csv) |\n\n"
      "```sh\nrayunits a < b\n```\n\n- one\n- two\n  continued\n\n1. first\n2. second\n\n"
      "<a id=\"sec1\"></a>\n\n## S\n\nText with ![plot](a.png) and `code`.\n";
  std::vector<std::string> missing;
  const std::string h = ru::report::markdown_to_html(md, d.p, "t", &missing);
  EXPECT_TRUE(missing.empty());
  EXPECT_NE(h.find("<h1>Title &lt;x&gt;</h1>"), std::string::npos) << h;
  EXPECT_EQ(count(h, "<table>"), 1);
  EXPECT_EQ(count(h, "<tr>"), 3);
  EXPECT_NE(h.find("<td><code>c|d</code></td><td class=\"r\"><strong>2</strong></td>"), std::string::npos) << h;
  EXPECT_NE(h.find("<a href=\"x.csv\">l</a>"), std::string::npos);
  EXPECT_NE(h.find("<pre><code>rayunits a &lt; b\n</code></pre>"), std::string::npos) << h;
  EXPECT_EQ(count(h, "<li>"), 4);
  EXPECT_NE(h.find("two continued"), std::string::npos) << h;
  EXPECT_NE(h.find("<a id=\"sec1\"></a>"), std::string::npos);
  const auto at = h.find("src=\"data:image/png;base64,");
  ASSERT_NE(at, std::string::npos);
  const auto b = at + std::string("src=\"data:image/png;base64,").size();
  EXPECT_EQ(unbase64(h.substr(b, h.find('"', b) - b)), png);
  EXPECT_NE(h.find("id=\"ru-verdict\""), std::string::npos);
  EXPECT_EQ(h.find("http"), std::string::npos);  // nothing from the network
  // a planted missing image is named
  ru::report::markdown_to_html("![x](nosuch.png)\n", d.p, "t", &missing);
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_EQ(missing[0], "nosuch.png");
}

// A small report with plots; its index.html embeds every image of index.md.
void small_report(const fs::path& out) {
  const auto r = ru::test::run_rayunits({"report", "--sections", "accuracy", "--quiet", "--out", out.string(), "--exp", "8",
                          "--frac", "10..11", "--samples", "2000"});
  ASSERT_EQ(r.code, 0) << r.err;
}

TEST(ReportHtml, SmallReportPageIsSelfContained) {
  Dir d;
  small_report(d.p / "rep");
  const std::string md = slurp(d.p / "rep" / "index.md"), h = slurp(d.p / "rep" / "index.html");
  ASSERT_FALSE(h.empty());
  const int images = count(md, "](") - count(md, "](#") - count(md, "](accuracy.csv)");
  EXPECT_EQ(count(md, "!["), 4) << md;
  EXPECT_EQ(images, 4);
  EXPECT_EQ(count(h, "<img "), 4);
  EXPECT_EQ(count(h, "src=\"data:image/png;base64,iVBORw0KGgo"), 4);  // the PNG signature, base64
  EXPECT_NE(h.find("<a id=\"accuracy\"></a>"), std::string::npos);
  EXPECT_NE(slurp(d.p / "rep" / "meta.json").find("index.html"), std::string::npos);
}

// Long: Debian's chromium, headless.
TEST(LongReportHtml, OpensInHeadlessChromium) {
  const std::string chromium = ru::util::find_program("chromium");
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh --long installs it)";
  Dir d;
  small_report(d.p / "rep");
  const fs::path page = d.p / "rep" / "index.html";
  auto browse = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> argv = {chromium, "--headless", "--no-sandbox", "--disable-gpu",
                                     "--disable-background-networking", "--user-data-dir=" + (d.p / "ud").string()};
    argv.insert(argv.end(), extra.begin(), extra.end());
    argv.push_back("file://" + page.string());
    ru::util::ProcessOptions o;
    o.out = ru::util::Redirect::capture();
    o.err = ru::util::Redirect::capture();
    o.timeout_s = 180;
    return ru::util::run_process(argv, o);
  };
  const auto dom = browse({"--dump-dom"});
  ASSERT_EQ(dom.status(), 0) << dom.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(dom.out, m, std::regex("id=\"ru-verdict\">([^<]*)<"))) << dom.out.substr(0, 2000);
  EXPECT_EQ(m[1].str(), "images 4/4; sections accuracy; verdict ok");
  // the screenshot: kept beside the build as a test artifact
  const fs::path shot = fs::path(RU_BINARY_DIR) / "Testing" / "report_html_screenshot.png";
  fs::create_directories(shot.parent_path());
  const auto sc = browse({"--window-size=1200,2000", "--screenshot=" + shot.string()});
  ASSERT_EQ(sc.status(), 0) << sc.err;
  EXPECT_EQ(slurp(shot).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // a planted broken image: the page's verdict says so
  {
    std::string h = slurp(page);
    const auto at = h.find("base64,iVBORw0KGgo");
    ASSERT_NE(at, std::string::npos);
    h.replace(at + 7, 12, "AAAAAAAAAAAA");
    std::ofstream(page, std::ios::binary) << h;
  }
  const auto bad = browse({"--dump-dom"});
  ASSERT_TRUE(std::regex_search(bad.out, m, std::regex("id=\"ru-verdict\">([^<]*)<")));
  EXPECT_EQ(m[1].str(), "images 3/4; sections accuracy; verdict broken-images");
}

}  // namespace
