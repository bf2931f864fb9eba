// A fresh folder under the test temp dir for the results_schema tests,
// removed afterwards (permissions restored first, for tests that take them
// away).
#ifndef BURRLAB_TESTS_RESULTS_SCHEMA_TEMP_DIR_H_
#define BURRLAB_TESTS_RESULTS_SCHEMA_TEMP_DIR_H_

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace burrlab::results_schema {

class TempDir {
 public:
  TempDir() {
    std::string pattern =
        (std::filesystem::path(testing::TempDir()) / "burrlab_results_XXXXXX")
            .string();
    path_ = mkdtemp(pattern.data());
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::permissions(path_, std::filesystem::perms::owner_all,
                                 std::filesystem::perm_options::add, ec);
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace burrlab::results_schema

#endif  // BURRLAB_TESTS_RESULTS_SCHEMA_TEMP_DIR_H_
