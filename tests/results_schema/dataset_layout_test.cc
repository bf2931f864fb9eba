// Tests of where a results folder keeps each session: the folder and file
// name prefix of a session with and without a label, and the listing of a
// folder's session folders in order, past anything that is not one.
#include "burrlab/results_schema/dataset_layout.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "temp_dir.h"

namespace burrlab::results_schema {
namespace {

namespace fs = std::filesystem;

TEST(DatasetLayout, NamesASessionWithAndWithoutALabel) {
  EXPECT_EQ(SessionFolder("out", "01", ""), fs::path("out/sub-01"));
  EXPECT_EQ(SessionFolder("out", "01", "2"), fs::path("out/sub-01/ses-2"));
  EXPECT_EQ(SessionFilePrefix("01", ""), "sub-01");
  EXPECT_EQ(SessionFilePrefix("01", "2"), "sub-01_ses-2");
  EXPECT_EQ(SessionName("01", ""), "sub-01");
  EXPECT_EQ(SessionName("01", "2"), "sub-01 ses-2");
}

TEST(DatasetLayout, ListsEverySubjectAndSessionFolderInOrder) {
  TempDir dir;
  for (const char* folder :
       {"sub-02", "sub-01/ses-2", "sub-01/ses-1", "sub-01/ses-x_y",
        "sub-01/beh", "sub-a_b", "code", "derivatives"}) {
    fs::create_directories(dir.path() / folder);
  }
  std::ofstream(dir.path() / "sub-03") << "a file";
  std::vector<std::string> found;
  for (const SessionFolderEntry& e : ListSessionFolders(dir.path())) {
    found.push_back(e.subject + "/" + e.session + " " +
                    fs::relative(e.folder, dir.path()).string());
  }
  EXPECT_EQ(found,
            (std::vector<std::string>{"01/ sub-01", "01/1 sub-01/ses-1",
                                      "01/2 sub-01/ses-2", "02/ sub-02"}));
  EXPECT_EQ(SessionLabelsOf(dir.path(), "01"),
            (std::vector<std::string>{"1", "2"}));
  EXPECT_TRUE(SessionLabelsOf(dir.path(), "09").empty());
  EXPECT_TRUE(ListSessionFolders(dir.path() / "missing").empty());
}

}  // namespace
}  // namespace burrlab::results_schema
