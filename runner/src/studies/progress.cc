// The progress bar: carriage return and redraw, cleared at the end.
#include "studies/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <string>

namespace burrlab::runner {

bool IsTerminalStderr(const std::ostream& stream) {
  return &stream == &std::cerr && isatty(STDERR_FILENO) == 1;
}

ProgressBar::ProgressBar(std::ostream& err, int total)
    : err_(err), total_(std::max(total, 1)), enabled_(IsTerminalStderr(err)) {}

ProgressBar::~ProgressBar() {
  if (enabled_) err_ << "\r\x1b[K" << std::flush;
}

void ProgressBar::Update(int done, std::string_view label) {
  if (!enabled_) return;
  constexpr int kWidth = 30;
  const int filled = std::clamp(done * kWidth / total_, 0, kWidth);
  err_ << fmt::format(
              "\r\x1b[K[{}{}] {}/{} {}",
              std::string(static_cast<std::size_t>(filled), '#'),
              std::string(static_cast<std::size_t>(kWidth - filled), '.'), done,
              total_, label)
       << std::flush;
}

}  // namespace burrlab::runner
