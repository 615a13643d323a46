#include "cli/yaml_config.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>

namespace vlpground::cli {
namespace {

constexpr const char* kOption = "--config";

std::vector<std::string> values_of(const std::string& key, const YAML::Node& value) {
  std::vector<std::string> out;
  if (value.IsScalar()) {
    out.push_back(value.as<std::string>());
  } else if (value.IsSequence()) {
    for (const auto& v : value) {
      if (!v.IsScalar()) throw std::runtime_error(key + ": expected a list of values");
      out.push_back(v.as<std::string>());
    }
  } else {
    throw std::runtime_error(key + ": expected a value or a list of values");
  }
  return out;
}

void apply_one(CLI::App& cmd, const std::string& key, const std::vector<std::string>& values) {
  CLI::Option* opt = cmd.get_option_no_throw("--" + key);
  if (opt == nullptr || opt->get_name() == kOption) {
    throw std::runtime_error("unknown option '" + key + "'");
  }
  if (opt->count() > 0) return;  // the command line wins
  if (opt->get_expected_min() == 0) {
    if (values.size() != 1) throw std::runtime_error(key + ": expected true or false");
    opt->add_result(opt->get_flag_value(key, values.front()));
  } else {
    opt->add_result(values);
  }
  opt->run_callback();
}

}  // namespace

void add_config_file_option(CLI::App& cmd) {
  cmd.add_option(kOption,
                 "read options from a YAML file: keys are long option names "
                 "('min-sensor-height: 0', 'extrinsics: [0, 0, 1.8, 0, 0, 0]'); the "
                 "command line wins")
      ->type_name("FILE.yaml")
      ->configurable(false);
}

void apply_config_file(CLI::App& cmd) {
  const CLI::Option* config = cmd.get_option_no_throw(kOption);
  if (config == nullptr || config->count() == 0) return;
  const std::string path = config->as<std::string>();
  const std::string where = std::string(kOption) + " " + path;
  if (std::filesystem::is_directory(path)) {
    throw CLI::FileError(where + ": is a directory");
  }
  if (!std::filesystem::exists(path)) throw CLI::FileError(where + ": no such file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw CLI::FileError(where + ": not valid YAML (" + e.msg + ")");
  }
  if (root.IsNull()) return;
  if (!root.IsMap()) throw CLI::FileError(where + ": expected a mapping of option names to values");
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    try {
      apply_one(cmd, key, values_of(key, entry.second));
    } catch (const CLI::Error& e) {
      throw CLI::FileError(where + ": " + key + ": " + e.what());
    } catch (const std::exception& e) {
      throw CLI::FileError(where + ": " + e.what());
    }
  }
}

}  // namespace vlpground::cli
