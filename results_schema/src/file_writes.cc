// Writing export files safely (see file_writes.h).
#include "file_writes.h"

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

namespace burrlab::results_schema {
namespace fs = std::filesystem;
namespace {

std::atomic<unsigned> g_temp_counter{0};

// The process id in a temporary export name "<file>.tmp-<pid>-<n>", or 0.
pid_t TempFileOwner(std::string_view name) {
  const std::size_t mark = name.rfind(".tmp-");
  if (mark == std::string_view::npos || mark == 0) return 0;
  std::string_view rest = name.substr(mark + 5);
  const std::size_t dash = rest.find('-');
  if (dash == std::string_view::npos || dash == 0 || dash + 1 == rest.size()) {
    return 0;
  }
  const auto all_digits = [](std::string_view text) {
    return std::all_of(text.begin(), text.end(), [](char c) {
      return std::isdigit(static_cast<unsigned char>(c)) != 0;
    });
  };
  const std::string_view pid = rest.substr(0, dash);
  if (!all_digits(pid) || !all_digits(rest.substr(dash + 1)) ||
      pid.size() > 9) {
    return 0;
  }
  return static_cast<pid_t>(std::stol(std::string(pid)));
}

Status WriteWholeFile(const fs::path& path, std::string_view bytes) {
  std::FILE* file = std::fopen(path.c_str(), "wbx");
  if (file == nullptr) return WriteError(path, errno);
  const bool wrote =
      std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
  const int write_errno = errno;
  if (std::fclose(file) != 0 || !wrote) {
    const int err = wrote ? errno : write_errno;
    std::remove(path.c_str());
    return WriteError(path, err);
  }
  return {};
}

}  // namespace

fs::path TempPathFor(const fs::path& path) {
  return fs::path(fmt::format("{}.tmp-{}-{}", path.string(), ::getpid(),
                              g_temp_counter.fetch_add(1)));
}

void RemoveStaleTempFiles(const fs::path& folder) {
  std::error_code ec;
  fs::directory_iterator it(folder, ec);
  if (ec) return;
  for (; it != fs::directory_iterator(); it.increment(ec)) {
    if (ec) return;
    const pid_t owner = TempFileOwner(it->path().filename().string());
    if (owner <= 0 || owner == ::getpid()) continue;
    if (::kill(owner, 0) == 0 || errno != ESRCH) continue;
    std::error_code ignored;
    fs::remove(it->path(), ignored);
  }
}

Error WriteError(const fs::path& path, int err) {
  return Error{
      fmt::format("cannot write {}: {}", path.string(), std::strerror(err))};
}

Status ReplaceFile(const fs::path& path, std::string_view bytes) {
  const fs::path temp = TempPathFor(path);
  if (Status s = WriteWholeFile(temp, bytes); !s) return s;
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(temp.c_str());
    return WriteError(path, err);
  }
  return {};
}

Status WriteIfAbsent(const fs::path& path, std::string_view bytes) {
  std::error_code ec;
  if (fs::symlink_status(path, ec).type() != fs::file_type::not_found)
    return {};
  const fs::path temp = TempPathFor(path);
  if (Status s = WriteWholeFile(temp, bytes); !s) return s;
  const int rc = ::link(temp.c_str(), path.c_str());
  const int err = errno;
  std::remove(temp.c_str());
  if (rc != 0 && err != EEXIST) return WriteError(path, err);
  return {};
}

}  // namespace burrlab::results_schema
