// PLACEHOLDER: replaced by the real command in this session.
#include "commands.h"
namespace meshlift::cli {
void register_info(CLI::App& app, int& exit_code) {
  app.add_subcommand("info", "(not yet built)")->callback([&exit_code] { exit_code = kInternal; });
}
}  // namespace meshlift::cli
