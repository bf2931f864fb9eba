// The progress bar: drawn on a terminal (a pseudo-terminal here), silent on
// anything else.
#include "studies/progress.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>

namespace burrlab::runner {
namespace {

// What a ProgressBar on std::cerr writes when file descriptor 2 is the slave
// side of a pseudo-terminal: 4 tasks, one update at 1 and one at 4, then the
// bar goes out of scope.
std::string DrawnOnATerminal() {
  int master = -1, slave = -1;
  if (openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) {
    ADD_FAILURE() << "no pseudo-terminal: " << std::strerror(errno);
    return "";
  }
  const pid_t pid = fork();
  if (pid == 0) {
    close(master);
    if (dup2(slave, STDERR_FILENO) < 0) _exit(2);
    {
      ProgressBar bar(std::cerr, 4);
      bar.Update(1, "sub-01");
      bar.Update(4, "done");
    }
    _exit(0);
  }
  close(slave);
  int status = 0;
  waitpid(pid, &status, 0);
  std::string out;
  char buffer[256];
  // The child has exited: read what it left, up to EIO (no slave left).
  fcntl(master, F_SETFL, O_NONBLOCK);
  while (true) {
    const ssize_t n = read(master, buffer, sizeof buffer);
    if (n <= 0) break;
    out.append(buffer, static_cast<std::size_t>(n));
  }
  close(master);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? out : "";
}

TEST(ProgressBar, DrawsOnATerminalAndClearsItsLineAtTheEnd) {
  EXPECT_EQ(DrawnOnATerminal(),
            "\r\x1b[K[#######.......................] 1/4 sub-01"
            "\r\x1b[K[##############################] 4/4 done"
            "\r\x1b[K");
}

TEST(ProgressBar, WritesNothingToAStreamThatIsNotTheTerminalStderr) {
  std::ostringstream log;
  {
    ProgressBar bar(log, 4);
    bar.Update(2, "sub-02");
  }
  EXPECT_EQ(log.str(), "");
  EXPECT_FALSE(IsTerminalStderr(log));
}

}  // namespace
}  // namespace burrlab::runner
