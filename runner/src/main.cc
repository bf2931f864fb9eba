// The burrlab executable: a thin layer over burrlab::runner::RunCli.
#include <iostream>
#include <string>
#include <vector>

#include "burrlab/runner/cli.h"

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  return burrlab::runner::RunCli(args, std::cout, std::cerr);
}
