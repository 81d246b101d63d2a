// slipstrip config-docs [docs/config.md] [--check]: docs/config.md's key
// tables are generated from the config schema (config/config_docs.hpp):
// rewrite them in place, or with --check report (exit 1) that the file
// differs from what the schema gives.
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "apps/cli.hpp"
#include "config/config_docs.hpp"

namespace slipstrip::cli {
namespace {

struct ConfigDocsOptions {
  std::string path = "docs/config.md";
  bool check = false;
};

int config_docs(const std::string& path, bool check) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("config-docs: cannot read '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string current = text.str();
  const std::string updated = update_config_docs(current);
  if (check) {
    if (updated == current) return 0;
    std::istringstream want(updated), have(current);
    std::string want_line, have_line;
    int line = 1;
    while (std::getline(want, want_line) && std::getline(have, have_line) && want_line == have_line)
      ++line;
    std::fprintf(stderr,
                 "error: %s is out of date with the config schema (config/config_schema.cpp), first "
                 "at line %d: run `slipstrip config-docs %s`\n",
                 path.c_str(), line, path.c_str());
    return 1;
  }
  if (updated != current) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << updated;
    out.close();
    if (!out) throw std::runtime_error("config-docs: cannot write '" + path + "'");
  }
  return 0;
}

}  // namespace

Command add_config_docs_command(CLI::App& app) {
  auto o = std::make_shared<ConfigDocsOptions>();
  auto* docs = app.add_subcommand("config-docs", "Regenerate the key tables of docs/config.md from the "
                                                 "config schema (config/config_schema.cpp)");
  docs->add_option("file", o->path, "The Markdown file holding the generated blocks")->capture_default_str();
  docs->add_flag("--check", o->check, "Change nothing; exit 1 if the file is out of date");
  return {docs, [o] { return config_docs(o->path, o->check); }};
}

}  // namespace slipstrip::cli
