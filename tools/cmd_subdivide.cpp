// PLACEHOLDER: replaced by the real command in this session.
#include "commands.h"
namespace meshlift::cli {
void register_subdivide(CLI::App& app, int& exit_code) {
  app.add_subcommand("subdivide", "(not yet built)")->callback([&exit_code] { exit_code = kInternal; });
}
}  // namespace meshlift::cli
