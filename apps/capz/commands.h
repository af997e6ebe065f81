// The capz CLI: one function per subcommand, each in its own cmd_*.cpp. They parse their own
// options (Boost.ProgramOptions), call the library and print; no codec logic lives here.
// Each returns the process exit status; library errors propagate as capz::Error and main()
// turns them into one line on stderr and the code's exit status.
#pragma once

#include <string>
#include <vector>

namespace capz_cli {

using Args = std::vector<std::string>;  // arguments after the subcommand name

int cmd_info(const Args& args);
int cmd_convert(const Args& args);
int cmd_compress(const Args& args);
int cmd_decompress(const Args& args);
int cmd_verify(const Args& args);
int cmd_test(const Args& args);
int cmd_list(const Args& args);

// Shared by commands: -q/-v level (0 quiet, 1 normal, 2 verbose).
extern int g_verbosity;

}  // namespace capz_cli
