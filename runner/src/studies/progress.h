// A one-line progress bar on stderr, drawn only when stderr is a terminal so
// that logs and pipes stay clean.
#ifndef BURRLAB_RUNNER_STUDIES_PROGRESS_H_
#define BURRLAB_RUNNER_STUDIES_PROGRESS_H_

#include <ostream>
#include <string_view>

namespace burrlab::runner {

// Whether `stream` is the process's std::cerr and file descriptor 2 is a
// terminal.
bool IsTerminalStderr(const std::ostream& stream);

class ProgressBar {
 public:
  // Draws on `err` only when IsTerminalStderr(err); `total` is the number of
  // tasks.
  ProgressBar(std::ostream& err, int total);
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  // Clears the line.
  ~ProgressBar();

  // Shows `done` of total tasks finished and what runs now.
  void Update(int done, std::string_view label);

 private:
  std::ostream& err_;
  int total_;
  bool enabled_;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STUDIES_PROGRESS_H_
