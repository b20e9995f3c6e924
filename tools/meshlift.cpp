// meshlift: multiresolution wavelet mesh codec, command-line front end.
#include <sys/resource.h>

#include <exception>
#include <filesystem>
#include <iostream>

#include "commands.h"

namespace meshlift::cli {

bool check_distinct_output(const std::string& input, const std::string& output) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool same = fs::exists(output, ec) && fs::equivalent(input, output, ec);
  if (same || input == output) {
    std::cerr << "meshlift: refusing to write " << output << ": it is the input file\n";
    return false;
  }
  return true;
}

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

}  // namespace meshlift::cli

int main(int argc, char** argv) {
  using namespace meshlift::cli;
  CLI::App app{"meshlift: multiresolution wavelet mesh codec"};
  app.require_subcommand(1);
  int exit_code = kOk;
  register_info(app, exit_code);
  register_subdivide(app, exit_code);
  register_limit(app, exit_code);
  register_fit(app, exit_code);
  register_encode(app, exit_code);
  register_decode(app, exit_code);
  register_truncate(app, exit_code);
  register_stream(app, exit_code);
  register_compare(app, exit_code);
  register_rd(app, exit_code);
  register_remesh(app, exit_code);
  register_gim(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kUsage;
  } catch (const std::exception& e) {
    std::cerr << "meshlift: internal error: " << e.what() << "\n";
    return kInternal;
  }
  return exit_code;
}
