// Placeholder until the command is implemented (see the open issues); it says so and fails.
#include <cstdio>

#include "commands.h"

namespace capz_cli {

int cmd_convert(const Args&) {
  std::fprintf(stderr, "capz convert: not implemented yet\n");
  return 7;
}

}  // namespace capz_cli
