// The reports rendered by a real browser: headless Chromium loads the generated index.html of a
// batch run; every replay has drawn its first frame, no script error was raised, the figures
// are in the DOM (the head-to-head section too) and decode as images; and a screenshot of the
// page is taken (a non-trivial PNG). And the tuning job's page: no script error, and every
// figure decodes as an image.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "rabbit/report/suite_report.h"
#include "report_fixture.h"
#include "tune_fixture.h"
#include "rabbit/report/tune_report.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;
using testing::Count;
using testing::ReadText;

// The first of names found executable on PATH, as a full path; empty when none.
std::string FindOnPath(const std::vector<std::string>& names) {
  const char* path = std::getenv("PATH");
  const std::string dirs = path == nullptr ? "" : path;
  for (const std::string& name : names) {
    size_t start = 0;
    while (start <= dirs.size()) {
      const size_t end = std::min(dirs.find(':', start), dirs.size());
      const fs::path candidate = fs::path(dirs.substr(start, end - start)) / name;
      if (!dirs.substr(start, end - start).empty() && ::access(candidate.c_str(), X_OK) == 0) {
        return candidate.string();
      }
      start = end + 1;
    }
  }
  return "";
}

// text as one shell word.
std::string ShellQuote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs a command line; its standard output (stderr discarded) and exit status.
int RunCommand(const std::string& command, std::string* output) {
  FILE* pipe = popen((command + " 2>/dev/null").c_str(), "r");
  if (pipe == nullptr) return -1;
  char buffer[65536];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) output->append(buffer, n);
  return pclose(pipe);
}

TEST(ReportRenderTest, ChromiumDrawsEveryReplayWithoutErrors) {
  const std::string chromium = FindOnPath({"chromium", "chromium-browser"});
  if (chromium.empty()) {
    GTEST_SKIP() << "neither chromium nor chromium-browser is on PATH: the page is not rendered";
  }
  const fs::path dir =
      fs::temp_directory_path() / ("rabbit_report_render_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const testing::ReportFixture fixture = testing::WriteReportFixture(dir.string(), 8.0);
  std::vector<std::string> warnings;
  const std::string page = WriteSuiteReport(fixture.dir, SuiteReportOptions{}, &warnings);
  const int figures = warnings.empty() ? fixture.expected_figures : 0;  // no gnuplot: none

  // Each Chromium gets its own profile, so that concurrent tests (and browsers) do not collide.
  const std::string browser = "timeout 60 " + ShellQuote(chromium) +
                              " --headless --no-sandbox --disable-gpu --hide-scrollbars "
                              "--user-data-dir=" +
                              ShellQuote((dir / "profile").string()) + " ";
  const std::string url = ShellQuote("file://" + page);
  std::string dom;
  ASSERT_EQ(RunCommand(browser + "--dump-dom " + url, &dom), 0) << "chromium failed";
  const size_t html = dom.find("<html");
  ASSERT_NE(html, std::string::npos) << dom.substr(0, 500);
  const std::string root = dom.substr(html, dom.find('>', html) - html);
  EXPECT_NE(root.find("data-js-errors=\"0\""), std::string::npos) << root;
  EXPECT_NE(root.find("data-replay=\"ready\""), std::string::npos) << root;
  EXPECT_NE(root.find("data-replay-count=\"" + std::to_string(fixture.runs.size()) + "\""),
            std::string::npos)
      << root;
  EXPECT_EQ(Count(dom, "<canvas"), static_cast<int>(fixture.runs.size()));
  EXPECT_EQ(Count(dom, "<img class=\"fig\""), figures);
  EXPECT_NE(dom.find("<section id=\"head-to-head\">"), std::string::npos);
  EXPECT_EQ(Count(dom, "<table class=\"comparison\">"), 2);
  // The play buttons were labelled by the script (it ran to the end for every replay).
  EXPECT_EQ(Count(dom, "\u25b6 Play</button>"), static_cast<int>(fixture.runs.size()));

  // Playback: a copy of the page that presses the first replay's Play button and reads its time
  // label after 2 s of the browser's virtual time (headless Chromium runs requestAnimationFrame
  // only on real frames, so the copy drives it by timers).
  {
    std::string harness = ReadText(page);
    harness.replace(harness.find("<script>"), 8,
                    "<script>window.requestAnimationFrame=function(cb){"
                    "return setTimeout(function(){cb(performance.now());},16);};");
    harness.replace(harness.rfind("</body>"), 7,
                    "<script>setTimeout(function(){"
                    "document.querySelector('.replay button.play').click();"
                    "setTimeout(function(){document.documentElement.dataset.played="
                    "document.querySelector('.replay .time').textContent;},2000);},50);"
                    "</script></body>");
    const fs::path play = dir / "play.html";
    testing::WriteText(play.string(), harness);
    std::string played;
    ASSERT_EQ(RunCommand(browser + "--virtual-time-budget=5000 --dump-dom " +
                             ShellQuote("file://" + play.string()),
                         &played),
              0);
    const size_t at = played.find("data-played=\"t = ");
    ASSERT_NE(at, std::string::npos) << played.substr(0, 300);
    const double t = std::atof(played.c_str() + at + 17);  // after `data-played="t = `
    EXPECT_GT(t, 0.5) << "the replay did not advance: " << played.substr(at, 40);
    EXPECT_NE(played.find("data-js-errors=\"0\""), std::string::npos);
  }

  // Every figure decodes as an image (the head-to-head's charts included).
  {
    std::string harness = ReadText(page);
    harness.replace(harness.rfind("</body>"), 7,
                    "<script>window.addEventListener('load',function(){var n=0;"
                    "for(var i=0;i<document.images.length;i++){var im=document.images[i];"
                    "if(im.complete&&im.naturalWidth>0)n++;}"
                    "document.documentElement.dataset.decoded=String(n);});</script></body>");
    const fs::path check = dir / "check.html";
    testing::WriteText(check.string(), harness);
    std::string checked;
    ASSERT_EQ(RunCommand(browser + "--virtual-time-budget=2000 --dump-dom " +
                             ShellQuote("file://" + check.string()),
                         &checked),
              0);
    EXPECT_NE(checked.find("data-decoded=\"" + std::to_string(figures) + "\""), std::string::npos)
        << checked.substr(0, 300);
  }

  const fs::path png = dir / "page.png";
  std::string ignored;
  ASSERT_EQ(RunCommand(browser + "--window-size=1400,3000 --screenshot=" +
                           ShellQuote(png.string()) + " " + url,
                       &ignored),
            0);
  ASSERT_TRUE(fs::exists(png));
  const std::string image = ReadText(png.string());
  EXPECT_EQ(image.compare(0, 8, "\x89PNG\r\n\x1a\n"), 0);
  const size_t kMinBytes = 50000;  // a blank 1400 x 3000 page compresses to a few kB
  EXPECT_GT(image.size(), kMinBytes);
  if (std::getenv("RABBIT_KEEP_REPORT") == nullptr) {
    fs::remove_all(dir);
  } else {
    std::printf("kept %s\n", dir.c_str());
  }
}

// The replay over a ground profile: the fixture's runs with a breakpoint in their first frame and
// one further on; every replay draws its frames (the first, and a seek to the middle) without a
// script error.
TEST(ReportRenderTest, ChromiumDrawsTheGroundProfileWithoutErrors) {
  const std::string chromium = FindOnPath({"chromium", "chromium-browser"});
  if (chromium.empty()) {
    GTEST_SKIP() << "neither chromium nor chromium-browser is on PATH: the page is not rendered";
  }
  const fs::path dir =
      fs::temp_directory_path() / ("rabbit_report_ground_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const testing::ReportFixture fixture = testing::WriteReportFixture(dir.string(), 6.0);
  for (const std::string& run : fixture.runs) {
    testing::WriteText((dir / run / "ground.csv").string(),
                       "x_start_m,slope_deg,height_m\n0.5,-3,0\n2,2,0.07861\n");
  }
  SuiteReportOptions options;
  options.gnuplot = "/nonexistent/gnuplot";  // the replays are the point here
  const std::string page = WriteSuiteReport(fixture.dir, options, nullptr);
  std::string harness = ReadText(page);
  harness.replace(harness.rfind("</body>"), 7,
                  "<script>window.addEventListener('load',function(){"
                  "var r=document.querySelectorAll('.replay input.seek');"
                  "for(var i=0;i<r.length;i++){r[i].value=String(Math.round(r[i].max/2));"
                  "r[i].dispatchEvent(new Event('input'));}"
                  "document.documentElement.dataset.seeked=String(r.length);});</script></body>");
  const fs::path check = dir / "check.html";
  testing::WriteText(check.string(), harness);
  const std::string browser = "timeout 60 " + ShellQuote(chromium) +
                              " --headless --no-sandbox --disable-gpu --hide-scrollbars "
                              "--user-data-dir=" +
                              ShellQuote((dir / "profile").string()) + " ";
  std::string dom;
  ASSERT_EQ(RunCommand(browser + "--virtual-time-budget=2000 --dump-dom " +
                           ShellQuote("file://" + check.string()),
                       &dom),
            0)
      << "chromium failed";
  const size_t html = dom.find("<html");
  ASSERT_NE(html, std::string::npos) << dom.substr(0, 500);
  const std::string root = dom.substr(html, dom.find('>', html) - html);
  EXPECT_NE(root.find("data-js-errors=\"0\""), std::string::npos) << root;
  EXPECT_NE(root.find("data-replay=\"ready\""), std::string::npos) << root;
  EXPECT_NE(root.find("data-seeked=\"" + std::to_string(fixture.runs.size()) + "\""),
            std::string::npos)
      << root;
  if (std::getenv("RABBIT_KEEP_REPORT") == nullptr) {
    fs::remove_all(dir);
  } else {
    std::printf("kept %s\n", dir.c_str());
  }
}

TEST(ReportRenderTest, ChromiumRendersTheTuningPageWithoutErrors) {
  const std::string chromium = FindOnPath({"chromium", "chromium-browser"});
  if (chromium.empty()) {
    GTEST_SKIP() << "neither chromium nor chromium-browser is on PATH: the page is not rendered";
  }
  const fs::path dir =
      fs::temp_directory_path() / ("rabbit_tune_render_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  testing::WriteTuneFixture(dir.string());
  std::vector<std::string> warnings;
  WriteTuneReport(dir.string(), TuneReportOptions{}, &warnings);
  const int figures = warnings.empty() ? 3 : 0;  // no gnuplot: none

  // A copy of the page that counts, once loaded, the images the browser could decode: an SVG
  // gnuplot wrote badly (say, an unescaped name) would load as a broken image.
  std::string harness = ReadText((dir / "index.html").string());
  harness.replace(harness.rfind("</body>"), 7,
                  "<script>window.addEventListener('load',function(){var n=0;"
                  "for(var i=0;i<document.images.length;i++){var im=document.images[i];"
                  "if(im.complete&&im.naturalWidth>0)n++;}"
                  "document.documentElement.dataset.decoded=String(n);});</script></body>");
  const fs::path page = dir / "check.html";
  testing::WriteText(page.string(), harness);
  const std::string browser = "timeout 60 " + ShellQuote(chromium) +
                              " --headless --no-sandbox --disable-gpu --hide-scrollbars "
                              "--user-data-dir=" +
                              ShellQuote((dir / "profile").string()) + " ";
  std::string dom;
  ASSERT_EQ(RunCommand(browser + "--virtual-time-budget=2000 --dump-dom " +
                           ShellQuote("file://" + page.string()),
                       &dom),
            0)
      << "chromium failed";
  const size_t html = dom.find("<html");
  ASSERT_NE(html, std::string::npos) << dom.substr(0, 500);
  const std::string root = dom.substr(html, dom.find('>', html) - html);
  EXPECT_NE(root.find("data-js-errors=\"0\""), std::string::npos) << root;
  EXPECT_NE(root.find("data-decoded=\"" + std::to_string(figures) + "\""), std::string::npos)
      << root;
  EXPECT_EQ(Count(dom, "<img class=\"fig\""), figures);
  EXPECT_NE(dom.find("<h1>Tuning job <em>walk_gains</em></h1>"), std::string::npos);
  if (std::getenv("RABBIT_KEEP_REPORT") == nullptr) {
    fs::remove_all(dir);
  } else {
    std::printf("kept %s\n", dir.c_str());
  }
}

}  // namespace
}  // namespace rabbit
