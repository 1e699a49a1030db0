#pragma once
// A command-line flag for a declared option (core/options.h): the flag binds the field itself,
// and its help is the declaration's, with the unit and the default the field really has, so no
// help string repeats a default by hand.
//
//   AddDeclaredOption(cmd, "--max-distance-m", options, "kriging.max_distance_m");
#include <CLI/CLI.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/options.h"

namespace ts {

class OptionFlagBinder : public OptionPath<OptionFlagBinder> {
 public:
  OptionFlagBinder(CLI::App* app, std::string flag, std::string path)
      : app_(app), flag_(std::move(flag)), path_(std::move(path)) {}
  template <class T>
  void operator()(const char* name, T& field, const OptionInfo& info) {
    if (Path(name) != path_) return;
    std::ostringstream help;
    help << info.help << " (";
    if constexpr (std::is_same_v<T, bool>)
      help << "default " << (field ? "on" : "off");
    else if constexpr (std::is_same_v<T, std::string>)
      help << "default '" << field << "'";
    else if constexpr (std::is_enum_v<T>)
      help << "default " << OptionNumber(field);
    else
      help << (*info.unit ? std::string(info.unit) + ", " : "") << "default " << field;
    help << ")";
    if constexpr (std::is_same_v<T, bool>)
      option = app_->add_flag(flag_, field, help.str());
    else
      option = app_->add_option(flag_, field, help.str());
  }
  CLI::Option* option = nullptr;

 private:
  CLI::App* app_;
  std::string flag_, path_;
};

// The flag for options' field at path ("kriging.max_distance_m"); a path that names no
// declared field is a programming error (thrown at start-up, caught by every command test).
template <class Options>
CLI::Option* AddDeclaredOption(CLI::App* app, const std::string& flag, Options& options,
                               const std::string& path) {
  OptionFlagBinder binder(app, flag, path);
  Options::Declare(options, binder);
  if (!binder.option) throw std::logic_error(flag + ": no declared option " + path);
  return binder.option;
}

// Sets the declared field at path from text ("ground.slope", "0.4"): for `--set NAME=VALUE`,
// any option of a step without a flag of its own. Ranges are checked where the options are.
class OptionSetter : public OptionPath<OptionSetter> {
 public:
  OptionSetter(std::string path, std::string text)
      : path_(std::move(path)), text_(std::move(text)) {}
  template <class T>
  void operator()(const char* name, T& field, const OptionInfo&) {
    if (Path(name) != path_) return;
    found = true;
    std::istringstream in(text_);
    if constexpr (std::is_same_v<T, std::string>) {
      field = text_;
      parsed = true;
    } else if constexpr (std::is_same_v<T, bool>) {
      parsed = text_ == "1" || text_ == "true" || text_ == "on" || text_ == "0" ||
               text_ == "false" || text_ == "off";
      if (parsed) field = text_ == "1" || text_ == "true" || text_ == "on";
    } else if constexpr (std::is_enum_v<T>) {
      long long v = 0;
      parsed = static_cast<bool>(in >> v) && in.peek() == EOF;
      if (parsed) field = static_cast<T>(v);
    } else {
      T v{};
      parsed = static_cast<bool>(in >> v) && in.peek() == EOF;
      if (parsed) field = v;
    }
  }
  bool found = false, parsed = false;

 private:
  std::string path_, text_;
};

// "NAME=VALUE" applied to options; the error names what was wrong, empty when set.
template <class Options>
std::string SetDeclaredOption(Options& options, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    return "--set " + assignment + ": expected NAME=VALUE (e.g. ground.slope=0.1)";
  OptionSetter setter(assignment.substr(0, eq), assignment.substr(eq + 1));
  Options::Declare(options, setter);
  if (!setter.found) return "--set " + assignment + ": no option " + assignment.substr(0, eq);
  if (!setter.parsed)
    return "--set " + assignment + ": " + assignment.substr(eq + 1) + " is not a value of " +
           assignment.substr(0, eq);
  return "";
}

}  // namespace ts
