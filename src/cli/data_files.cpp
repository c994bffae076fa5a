// Shipped data files (see data_files.hpp).
#include "data_files.hpp"

#include <sys/stat.h>

#include <cstdlib>

#ifndef TMPC_DATA_DIR
#define TMPC_DATA_DIR ""
#endif

namespace tmpc::cli {

namespace {
bool exists(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0;
}
}  // namespace

std::string data_file(const std::string& relative) {
  if (relative.empty() || relative[0] == '/' || exists(relative)) return relative;
  const char* env = std::getenv("TMPC_DATA_DIR");
  for (const std::string dir : {std::string(env != nullptr ? env : ""), std::string(TMPC_DATA_DIR)}) {
    if (!dir.empty() && exists(dir + "/" + relative)) return dir + "/" + relative;
  }
  return relative;
}

}  // namespace tmpc::cli
