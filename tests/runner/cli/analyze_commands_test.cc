// `burrlab analyze fit` and `burrlab analyze dprime` as a user meets them:
// JSON keys, the _beh.tsv path, the plot, and the exact text and exit code
// of every bad input.
#include "cli/analyze_commands.h"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "run_cli.h"

namespace burrlab::runner {
namespace {

using ::testing::HasSubstr;

// A file in a fresh temporary folder, removed with the fixture.
class AnalyzeCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("burrlab_analyze_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& text) {
    const std::filesystem::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
  }
  // Expects exit code 1, nothing on stdout and exactly `text` on stderr.
  void ExpectFitError(const std::string& file, const std::string& sigmoid,
                      const std::string& text) {
    const CliRun run =
        RunBurrlab({"analyze", "fit", "--data", file, "--task", "2afc",
                    "--sigmoid", sigmoid, "--bootstrap", "0"});
    EXPECT_EQ(run.code, 1);
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(run.err, text);
  }
  std::filesystem::path dir_;
};

constexpr char kCounts[] =
    "level,n_correct,n_total\n1,26,40\n2,19,40\n3,25,40\n4,32,40\n5,40,40\n"
    "6,39,40\n";

TEST_F(AnalyzeCommand, FitPrintsTheJsonKeysOfTheIssue) {
  const std::string data = Write("d.csv", kCounts);
  const CliRun run = RunBurrlab({"analyze", "fit", "--data", data, "--task",
                                 "2afc", "--sigmoid", "logistic", "--bootstrap",
                                 "199", "--seed", "3", "--json"});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::ordered_json j = nlohmann::ordered_json::parse(run.out);
  std::vector<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.push_back(key);
  const std::vector<std::string> first = {
      "alpha",    "beta",       "gamma",     "lambda",     "log_likelihood",
      "deviance", "deviance_p", "converged", "thresholds", "slopes"};
  ASSERT_GE(keys.size(), first.size());
  EXPECT_EQ(std::vector<std::string>(keys.begin(), keys.begin() + 10), first);
  EXPECT_TRUE(j["converged"].get<bool>());
  EXPECT_EQ(j["gamma"].get<double>(), 0.5);
  ASSERT_EQ(j["thresholds"].size(), 3u);
  const auto& t = j["thresholds"][1];
  EXPECT_EQ(t["cut"].get<double>(), 0.5);
  std::vector<std::string> conf;
  for (const auto& [key, value] : t["ci"].items()) conf.push_back(key);
  EXPECT_EQ(conf, (std::vector<std::string>{"0.023", "0.159", "0.841", "0.977",
                                            "0.025", "0.975"}));
  EXPECT_LT(t["ci"]["0.025"].get<double>(), t["value"].get<double>());
  EXPECT_GT(t["ci_percentile"]["0.975"].get<double>(),
            t["value"].get<double>());
  EXPECT_EQ(j["slopes"][0].size(), 2u);  // cut, value
  EXPECT_EQ(j["bootstrap_samples"].get<int>(), 199);
  EXPECT_EQ(j["data"]["format"], "counts");
  // psignifit 2.5.6 on the same data: alpha 3.69986, beta 0.377672.
  EXPECT_NEAR(j["alpha"].get<double>(), 3.69986, 0.005 * 3.69986);
  EXPECT_NEAR(j["beta"].get<double>(), 0.377672, 0.005 * 0.377672);
}

TEST_F(AnalyzeCommand, FitPoolsABehTsvAndWritesThePlot) {
  std::string beh = "trial_index\tstim_level\tcorrect\tresponse\n";
  int index = 0;
  const int correct[4] = {11, 14, 18, 20};
  for (int level = 1; level <= 4; ++level) {
    for (int k = 0; k < 20; ++k) {
      beh += std::to_string(index++) + "\t" + std::to_string(level) + "\t" +
             (k < correct[level - 1] ? "1" : "0") + "\tA\n";
    }
  }
  beh += std::to_string(index) + "\tn/a\tn/a\tn/a\n";
  const std::string data = Write("sub-01_task-x_beh.tsv", beh);
  const std::string png = (dir_ / "fit.png").string();
  const CliRun run = RunBurrlab({"analyze", "fit", "--data", data, "--task",
                                 "yesno", "--sigmoid", "weibull", "--bootstrap",
                                 "99", "--json", "--plot", png});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["data"]["format"], "trials");
  EXPECT_EQ(j["data"]["levels"], 4);
  EXPECT_EQ(j["data"]["rows"], 80);
  EXPECT_EQ(j["data"]["skipped_rows"], 1);
  EXPECT_EQ(j["task"], "yesno");
  std::ifstream file(png, std::ios::binary);
  std::string magic(8, '\0');
  file.read(magic.data(), 8);
  EXPECT_EQ(magic, "\x89PNG\r\n\x1a\n");
}

// The figure's format follows the --plot path's extension; a path of
// another extension is an error naming it.
TEST_F(AnalyzeCommand, FitPlotIsAPdfOrSvgByItsExtension) {
  const std::string data = Write("d.csv", kCounts);
  for (const std::string& name :
       {std::string("fit.pdf"), std::string("fit.SVG")}) {
    const std::string path = (dir_ / name).string();
    const CliRun run = RunBurrlab({"analyze", "fit", "--data", data, "--task",
                                   "2afc", "--sigmoid", "logistic",
                                   "--bootstrap", "0", "--plot", path});
    ASSERT_EQ(run.code, 0) << run.err;
    std::ifstream file(path, std::ios::binary);
    std::string head(5, '\0');
    file.read(head.data(), 5);
    EXPECT_EQ(head, name == "fit.pdf" ? "%PDF-" : "<?xml") << name;
  }
  const std::string bmp = (dir_ / "fit.bmp").string();
  const CliRun run =
      RunBurrlab({"analyze", "fit", "--data", data, "--task", "2afc",
                  "--sigmoid", "logistic", "--bootstrap", "0", "--plot", bmp});
  EXPECT_NE(run.code, 0);
  EXPECT_NE(run.err.find(bmp + ": cannot tell the figure format from the "
                               "extension '.bmp'; use .png, .pdf or .svg"),
            std::string::npos)
      << run.err;
}

TEST_F(AnalyzeCommand, FitOfOneRowPerTrialIsTheFitOfThePooledCounts) {
  // kCounts' 240 trials as one row per trial and as a _beh.tsv, both in a
  // scrambled order, and as two rows per level, last level first.
  const int correct[6] = {26, 19, 25, 32, 40, 39};
  std::string rows = "level,n_correct,n_total\n";
  std::string beh = "trial_index\tstim_level\tcorrect\n";
  for (int t = 0; t < 240; ++t) {
    const int scrambled = (t * 37) % 240;
    const int k = scrambled / 40, i = scrambled % 40;
    const std::string level = std::to_string(k + 1);
    const std::string answer = i < correct[k] ? "1" : "0";
    rows += level + "," + answer + ",1\n";
    beh += std::to_string(t) + "\t" + level + "\t" + answer + "\n";
  }
  std::string split = "level,n_correct,n_total\n";
  for (int k = 5; k >= 0; --k) {
    const int first = std::min(correct[k], 15);
    split += std::to_string(k + 1) + "," + std::to_string(first) + ",15\n" +
             std::to_string(k + 1) + "," + std::to_string(correct[k] - first) +
             ",25\n";
  }
  const auto fit = [&](const std::string& path, bool json) {
    std::vector<std::string> args = {
        "analyze",   "fit",      "--data",      path,  "--task", "2afc",
        "--sigmoid", "logistic", "--bootstrap", "199", "--seed", "3"};
    if (json) args.push_back("--json");
    const CliRun run = RunBurrlab(args);
    EXPECT_EQ(run.code, 0) << run.err;
    return run.out;
  };
  const std::string counts = Write("counts.csv", kCounts);
  const std::string text = fit(counts, false);
  const std::string data_line = "data       " + counts + " (6 levels)\n";
  ASSERT_TRUE(text.starts_with(data_line)) << text;
  const std::string report = text.substr(data_line.size());
  nlohmann::json expected = nlohmann::json::parse(fit(counts, true));
  EXPECT_EQ(expected["data"]["rows"], 6);
  expected.erase("data");
  for (const auto& [name, contents, pooled_rows] :
       {std::tuple{"rows.csv", rows, 240}, std::tuple{"split.csv", split, 12},
        std::tuple{"sub-01_task-x_beh.tsv", beh, 240}}) {
    SCOPED_TRACE(name);
    const std::string path = Write(name, contents);
    EXPECT_EQ(fit(path, false), "data       " + path +
                                    " (6 levels)\npooled     " +
                                    std::to_string(pooled_rows) +
                                    " rows into 6 levels\n" + report);
    nlohmann::json j = nlohmann::json::parse(fit(path, true));
    EXPECT_EQ(j["data"]["rows"], pooled_rows);
    j.erase("data");
    EXPECT_EQ(j.dump(), expected.dump());
  }
}

TEST_F(AnalyzeCommand, FitReportsABoundWithAWarningOnStderr) {
  const std::string data =
      Write("d.csv",
            "level,n_correct,n_total\n1,21,40\n2,24,40\n3,29,40\n4,35,40\n"
            "5,38,40\n6,40,40\n");
  const CliRun run =
      RunBurrlab({"analyze", "fit", "--data", data, "--task", "2afc",
                  "--sigmoid", "logistic", "--bootstrap", "0"});
  ASSERT_EQ(run.code, 0);
  EXPECT_THAT(run.out, HasSubstr("lambda     0  (at lower bound)\n"));
  EXPECT_EQ(run.err,
            "burrlab: warning: lambda = 0 is at the lower limit of its range "
            "[0, 0.05]\n");
}

TEST_F(AnalyzeCommand, FitThatDoesNotConvergeExitsTwoAndSaysSo) {
  // Three likelihood evaluations per start cannot reach the maximum: the
  // results are printed, flagged, and the exit code is 2.
  const std::string data = Write("d.csv", kCounts);
  const CliRun run = RunBurrlab({"analyze", "fit", "--data", data, "--task",
                                 "2afc", "--sigmoid", "logistic", "--bootstrap",
                                 "0", "--max-evaluations", "3", "--json"});
  EXPECT_EQ(run.code, 2);
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["converged"], false);
  EXPECT_THAT(run.err, HasSubstr("burrlab: warning: "));
  EXPECT_THAT(run.err, HasSubstr("converge"));
  const CliRun enough =
      RunBurrlab({"analyze", "fit", "--data", data, "--task", "2afc",
                  "--sigmoid", "logistic", "--bootstrap", "0", "--json"});
  EXPECT_EQ(enough.code, 0);
}

TEST_F(AnalyzeCommand, FitRejectsEachBadInputWithAClearMessage) {
  ExpectFitError(Write("empty.csv", ""), "logistic",
                 (dir_ / "empty.csv").string() +
                     ": error: the file is empty; expected a header line "
                     "level,n_correct,n_total (CSV or TSV) or a _beh.tsv with "
                     "stim_level and correct columns\n");
  ExpectFitError(
      Write("cell.csv", "level,n_correct,n_total\n1,20,40\n2,x,40\n"),
      "logistic",
      (dir_ / "cell.csv").string() +
          ":3:3: error: n_correct 'x' is not a whole number of at least "
          "0\n2,x,40\n  ^\n");
  ExpectFitError(
      Write("over.csv", "level,n_correct,n_total\n1,20,40\n2,45,40\n"),
      "logistic",
      (dir_ / "over.csv").string() +
          ":3:3: error: n_correct = 45 exceeds n_total = 40\n2,45,40\n  ^\n");
  ExpectFitError(
      Write("zero.csv", "level,n_correct,n_total\n1,20,40\n0,30,40\n3,38,40\n"),
      "weibull",
      (dir_ / "zero.csv").string() +
          ":3:1: error: level 0 must be positive for the Weibull, which uses "
          "(x / alpha)^beta\n0,30,40\n^\n");
  ExpectFitError(
      Write("two.csv", "level,n_correct,n_total\n1,20,40\n2,30,40\n"),
      "logistic",
      (dir_ / "two.csv").string() +
          ": error: only 2 distinct levels: a psychometric fit "
          "needs at least 3\n");
  ExpectFitError(
      Write("all.csv", "level,n_correct,n_total\n1,40,40\n2,40,40\n3,40,40\n"),
      "logistic",
      (dir_ / "all.csv").string() +
          ": error: all 120 trials are correct (or 'yes'): the data do not "
          "constrain a psychometric function; test lower levels\n");
  ExpectFitError((dir_ / "missing.csv").string(), "logistic",
                 "burrlab: cannot read " + (dir_ / "missing.csv").string() +
                     ": No such file or directory\n");
}

TEST_F(AnalyzeCommand, FitRejectsBadFlagsNamingThem) {
  const std::string data = Write("d.csv", kCounts);
  const auto expect = [&](std::vector<std::string> flags,
                          const std::string& line) {
    std::vector<std::string> args = {"analyze", "fit", "--data", data};
    args.insert(args.end(), flags.begin(), flags.end());
    const CliRun run = RunBurrlab(args);
    EXPECT_EQ(run.code, 1);
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(run.err, "burrlab: " + line + "\n");
  };
  expect({"--task", "3afc", "--sigmoid", "logistic"},
         "--task must be '2afc', 'yesno' or 'nafc:N' with N from 2 to 100, "
         "got '3afc'");
  expect({"--task", "2afc", "--sigmoid", "probit"},
         "--sigmoid must be 'logistic', 'cumnorm', 'weibull' or 'gumbel', got "
         "'probit'");
  expect({"--task", "2afc", "--sigmoid", "logistic", "--cuts", "0.5,1"},
         "--cuts must be numbers in (0, 1) separated by commas, got '0.5,1'");
  expect({"--task", "2afc", "--sigmoid", "logistic", "--gamma-max", "0.1"},
         "--gamma-max applies to --task yesno only (n-AFC fixes gamma at 1/N)");
  expect({"--task", "2afc", "--sigmoid", "logistic", "--lambda-max", "1"},
         "--lambda-max must be below 1, got '1'");
}

// --by fits each condition and compares them; the numbers against R's glm
// with psyphy's mafc.logit(2) link (tests/analysis/fixtures/r/
// make_condition_comparison_fixture.R, case threshold_shift, logistic), no
// lapses: the separate and shared-slope thresholds and both likelihood
// ratios within 1 %, the chi-square p-values too. The file has CR LF line
// ends and the condition column between the others.
TEST_F(AnalyzeCommand, FitByConditionComparesThemAsRDoes) {
  const std::string data =
      Write("conditions.csv",
            "level,condition,n_correct,n_total\r\n"
            "0.5,a,22,40\r\n1,a,25,40\r\n1.5,a,29,40\r\n2,a,33,40\r\n"
            "2.5,a,37,40\r\n3,a,39,40\r\n0.5,b,20,40\r\n1,b,22,40\r\n"
            "1.5,b,24,40\r\n2,b,28,40\r\n2.5,b,32,40\r\n3,b,36,40\r\n");
  const std::string plot = (dir_ / "conditions.svg").string();
  const CliRun run = RunBurrlab(
      {"analyze", "fit", "--data", data, "--task", "2afc", "--sigmoid",
       "logistic", "--by", "condition", "--lambda-max", "0", "--cuts", "0.5",
       "--bootstrap", "200", "--json", "--plot", plot});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  ASSERT_EQ(j["conditions"].size(), 2u);
  EXPECT_EQ(j["conditions"][1]["name"], "b");
  // R: separate model, alpha per condition (-b0/b1).
  EXPECT_NEAR(j["models"][0]["conditions"][0]["alpha"].get<double>(), 1.6185376,
              0.01 * 1.6185376);
  EXPECT_NEAR(j["models"][0]["conditions"][1]["alpha"].get<double>(), 2.2535939,
              0.01 * 2.2535939);
  EXPECT_EQ(j["models"][1]["model"], "shared slope");
  EXPECT_NEAR(j["models"][1]["conditions"][0]["alpha"].get<double>(), 1.6102840,
              0.01 * 1.6102840);
  EXPECT_NEAR(j["models"][1]["conditions"][1]["beta"].get<double>(), 0.52101976,
              0.01 * 0.52101976);
  EXPECT_EQ(j["tests"][0]["question"], "thresholds differ");
  EXPECT_NEAR(j["tests"][0]["lr"].get<double>(), 8.4198620, 0.01 * 8.4198620);
  EXPECT_NEAR(j["tests"][0]["p_chi_square"].get<double>(), 0.0037114396,
              0.01 * 0.0037114396);
  EXPECT_NEAR(j["tests"][1]["lr"].get<double>(), 0.031339110,
              0.01 * 0.031339110);
  EXPECT_NEAR(j["tests"][1]["p_chi_square"].get<double>(), 0.85948596,
              0.01 * 0.85948596);
  EXPECT_EQ(j["tests"][0]["bootstrap_samples"], 200);
  EXPECT_TRUE(std::filesystem::exists(plot));

  const CliRun text =
      RunBurrlab({"analyze", "fit", "--data", data, "--task", "2afc",
                  "--sigmoid", "logistic", "--by", "condition", "--lambda-max",
                  "0", "--cuts", "0.5", "--bootstrap", "0"});
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_THAT(text.out,
              HasSubstr("  thresholds differ (shared vs shared slope): LR "
                        "8.42, df 1, p 0.003711 chi-square, p n/a bootstrap "
                        "(--bootstrap 0)\n"));
}

TEST_F(AnalyzeCommand, FitByConditionNamesWhatIsMissing) {
  const std::string one =
      Write("one.csv",
            "level,condition,n_correct,n_total\n1,a,22,40\n2,a,30,40\n"
            "3,a,38,40\n");
  CliRun run = RunBurrlab({"analyze", "fit", "--data", one, "--task", "2afc",
                           "--sigmoid", "logistic", "--by", "condition"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: --by condition: the data have 1 condition ('a'); "
            "comparing needs at least 2\n");
  run = RunBurrlab({"analyze", "fit", "--data", dir_.string(), "--task", "2afc",
                    "--sigmoid", "logistic"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err, fmt::format("burrlab: --data {0} is a folder; 'burrlab "
                                 "analyze thresholds {0}' fits every "
                                 "subject's constant-stimuli blocks and "
                                 "reports the group, and --data takes one "
                                 "file (e.g. a subject's _beh.tsv under "
                                 "{0}/sub-*/beh/)\n",
                                 dir_.string()));
  run = RunBurrlab({"analyze", "fit", "--data", one, "--task", "2afc",
                    "--sigmoid", "logistic", "--by", "group"});
  EXPECT_EQ(run.code, 1);
  EXPECT_THAT(run.err, HasSubstr("error: the header has no column 'group' to "
                                 "split the rows by"));
  const std::string two_levels =
      Write("two.csv",
            "level,condition,n_correct,n_total\n1,a,22,40\n2,a,30,40\n"
            "3,a,38,40\n1,b,22,40\n2,b,30,40\n");
  run = RunBurrlab({"analyze", "fit", "--data", two_levels, "--task", "2afc",
                    "--sigmoid", "logistic", "--by", "condition"});
  EXPECT_EQ(run.code, 1);
  EXPECT_THAT(run.err, HasSubstr("error: condition 'b': only 2 distinct "
                                 "levels: a psychometric fit needs at least "
                                 "3"));
}

TEST(AnalyzeDPrime, PrintsJsonForEachDesign) {
  CliRun run = RunBurrlab({"analyze", "dprime", "--design", "same-different",
                           "--hit", "0.6", "--fa", "0.1", "--json"});
  ASSERT_EQ(run.code, 0) << run.err;
  nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_NEAR(j["dprime"].get<double>(), 2.6837, 1e-4);  // Palamedes
  EXPECT_EQ(j["model"], "differencing");
  run = RunBurrlab({"analyze", "dprime", "--design", "same-different",
                    "--model", "independent-observation", "--hit", "0.9",
                    "--fa", "0.6", "--json"});
  EXPECT_NEAR(nlohmann::json::parse(run.out)["dprime"].get<double>(), 1.7808,
              1e-4);
  run = RunBurrlab({"analyze", "dprime", "--design", "2afc", "--pc", "0.76"});
  EXPECT_EQ(run.out, "d' = 0.998863 (2afc; Pc 0.76)\n");
  run = RunBurrlab({"analyze", "dprime", "--design", "yesno", "--hit", "0.69",
                    "--fa", "0.31", "--json"});
  EXPECT_NEAR(nlohmann::json::parse(run.out)["dprime"].get<double>(),
              0.99170069469490629, 1e-12);
}

TEST(AnalyzeDPrime, RejectsMismatchedFlagsAndRates) {
  const auto expect = [](std::vector<std::string> flags,
                         const std::string& line) {
    std::vector<std::string> args = {"analyze", "dprime"};
    args.insert(args.end(), flags.begin(), flags.end());
    const CliRun run = RunBurrlab(args);
    EXPECT_EQ(run.code, 1);
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(run.err, "burrlab: " + line + "\n");
  };
  expect({"--design", "yesno", "--pc", "0.7"},
         "--design yesno takes --hit H and --fa F (not --pc)");
  expect({"--design", "2afc", "--hit", "0.7", "--fa", "0.2"},
         "--design 2afc takes --pc P (not --hit/--fa)");
  expect({"--design", "2afc", "--pc", "0.7", "--model", "differencing"},
         "--model applies to --design same-different only");
  expect({"--design", "abx", "--pc", "0.7"},
         "--design must be 'yesno', '2afc', 'nafc:N' or 'same-different', got "
         "'abx'");
  expect({"--design", "yesno", "--hit", "1", "--fa", "0.3"},
         "analyze dprime: the hit rate must be in (0, 1), got 1 (correct "
         "rates of 0 or 1 first, e.g. to 1/(2N) or 1 - 1/(2N))");
}

}  // namespace
}  // namespace burrlab::runner
