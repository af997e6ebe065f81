// Placeholder until the command is implemented (see the open issues); it says so and fails.
#include <cstdio>

#include "commands.h"

namespace capz_cli {

int cmd_info(const Args&) {
  std::fprintf(stderr, "capz info: not implemented yet\n");
  return 7;
}

}  // namespace capz_cli
