// `burrlab study --renderings`: a simulated study sharing renderings
// (studies/rendering_pool.h) is reproducible for any number of jobs, and each
// trial says so. (Moved from studies/rendering_pool_test.cc: it runs the
// CLI, so it belongs to the CLI's test binary.)
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "../results_schema/temp_dir.h"
#include "read_file.h"
#include "run_cli.h"

namespace burrlab::runner {
namespace {

using results_schema::TempDir;

TEST(StudyWithRenderings, IsTheSameForOneOrTwoJobsAndSaysSoInEachTrial) {
  TempDir dir;
  std::vector<std::string> outputs;
  for (const char* jobs : {"1", "2"}) {
    const std::filesystem::path out = dir.path() / (std::string("j") + jobs);
    const CliRun run = RunBurrlab(
        {"study", ExamplePath("two_interval_2afc.toml"), "--simulated-subjects",
         "3", "--out", out.string(), "--renderings", "2", "--jobs", jobs,
         "--weber-spread", "0.5"});
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_THAT(run.out, testing::HasSubstr("3 of 3 simulated subjects"));
    std::string all;
    for (const char* sub : {"sub-01", "sub-02", "sub-03"}) {
      for (const auto& e :
           std::filesystem::directory_iterator(out / sub / "beh")) {
        if (e.path().extension() == ".tsv" ||
            e.path().string().ends_with(".tsv.gz")) {
          all += e.path().filename().string() + ReadFile(e.path());
        }
      }
    }
    EXPECT_THAT(all, testing::HasSubstr("\"rendering_pool\":2"));
    outputs.push_back(all);
  }
  EXPECT_FALSE(outputs[0].empty());
  EXPECT_EQ(outputs[0], outputs[1]);
}

}  // namespace
}  // namespace burrlab::runner
