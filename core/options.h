#pragma once
// Each option declared once (PDAL's addArgs, COLMAP's OptionManager). An options struct lists
// its fields in one static template
//
//   template <class Self, class Visitor> static void Declare(Self& self, Visitor& v) {
//     v("max_distance_m", self.max_distance_m, {"nodata where the nearest point is farther",
//                                               "m", 0.5, 50});
//     v.Group("variogram", self.variogram);
//   }
//
// with the help, the unit and the range a real rig, site or survey can have; the default is the
// field's initialiser. From that one list come the check of every field (named, with its
// value), the options in report.json, and the command line's help with the real default
// (station/option_flags.h). Self is the struct, const or not, so one list serves reading and
// binding.
#include <chrono>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace ts {

struct OptionInfo {
  const char* help = "";
  const char* unit = "";  // "m", "px", "deg", "us", ... ; "" for counts and flags
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
};

// A field's value as a number, for the range check and the JSON (durations in their unit).
template <class T>
double OptionNumber(const T& value) {
  if constexpr (std::is_enum_v<T>)
    return static_cast<double>(static_cast<std::underlying_type_t<T>>(value));
  else if constexpr (std::is_arithmetic_v<T>)
    return static_cast<double>(value);
  else
    return static_cast<double>(value.count());  // std::chrono::duration
}

inline std::string OptionNumberText(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// Visits groups with their dotted path ("kriging.variogram.max_lag_m"); Visitor is the class
// that derives from it, which each group's Declare visits in turn.
template <class Visitor>
class OptionPath {
 public:
  template <class Sub>
  void Group(const char* name, Sub& sub) {
    groups_.push_back(name);
    std::remove_cv_t<Sub>::Declare(sub, static_cast<Visitor&>(*this));
    groups_.pop_back();
  }

 protected:
  std::string Path(const char* name) const {
    std::string path;
    for (const std::string& g : groups_) path += g + ".";
    return path + name;
  }
  std::vector<std::string> groups_;
};

// The first field outside its range (or not finite), named with its value.
class OptionChecker : public OptionPath<OptionChecker> {
 public:
  template <class T>
  void operator()(const char* name, const T& value, const OptionInfo& info) {
    if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, bool> || std::is_enum_v<T>) {
      return;
    } else {
      if (!error_.empty()) return;
      const double v = OptionNumber(value);
      if (std::isfinite(v) && v >= info.min && v <= info.max) return;
      error_ = Path(name) + " must be in [" + OptionNumberText(info.min) + ", " +
               OptionNumberText(info.max) + "]" + (*info.unit ? std::string(" ") + info.unit : "") +
               ", got " + OptionNumberText(v);
    }
  }
  const std::string& error() const { return error_; }

 private:
  std::string error_;
};

class OptionJsonWriter {
 public:
  template <class T>
  void operator()(const char* name, const T& value, const OptionInfo&) {
    if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, bool>)
      (*json_)[name] = value;
    else
      (*json_)[name] = OptionNumber(value);
  }
  template <class Sub>
  void Group(const char* name, const Sub& sub) {
    nlohmann::json* outer = json_;
    json_ = &(*outer)[name];
    *json_ = nlohmann::json::object();
    std::remove_cv_t<Sub>::Declare(sub, *this);
    json_ = outer;
  }
  nlohmann::json json = nlohmann::json::object();

 private:
  nlohmann::json* json_ = &json;
};

// Every declared field in range; why names the first that is not.
template <class Options>
bool CheckDeclaredOptions(const Options& options, std::string* why) {
  OptionChecker checker;
  Options::Declare(options, checker);
  if (checker.error().empty()) return true;
  if (why) *why = checker.error();
  return false;
}

template <class Options>
nlohmann::json DeclaredOptionsToJson(const Options& options) {
  OptionJsonWriter writer;
  Options::Declare(options, writer);
  return writer.json;
}

}  // namespace ts
