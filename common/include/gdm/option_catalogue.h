// The catalogue of options: the one place that names, documents and bounds
// every numeric, on/off and choice option of the model (name, group, unit,
// default, range, help). Every front end reads it: the gdm command builds its
// flags (--name-with-dashes) and --help from it, the MeshLab filters their
// parameters, the README's option list is generated from it, and validate()
// checks options against it, so a range is checked in one place. Adding an
// option is its field (with its commented default) plus one line here.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "gdm/deformer.h"
#include "gdm/errors.h"

namespace gdm {

enum class OptionType { real, integer, boolean, choice };

// What an option is, independent of the struct it lives in.
struct OptionInfo {
  std::string name;    // the field's name, spelled the same by every front end (CLI: --lod-face-area)
  std::string group;   // heading in --help and the docs
  std::string unit;    // "mm", "voxels", ...; empty when none
  std::string help;    // one sentence
  OptionType type = OptionType::real;
  double lo = 0.0;                                       // smallest value (real, integer)
  double hi = std::numeric_limits<double>::infinity();   // largest value
  bool lo_open = false;                                  // lo itself excluded
  bool hi_open = false;                                  // hi itself excluded
  std::vector<double> special;       // values accepted outside [lo, hi] (0 = off, inf = off)
  std::string special_text;          // what they mean, e.g. "0 (off)"; shown before the range
  std::vector<std::string> choices;  // OptionType::choice: value i means choices[i]
  std::string alias;                 // an older command-line spelling, without dashes; empty when none
};

// An option of the struct `Options` (DeformOptions, PipelineOptions): its
// value as a double (booleans 0/1, choices their index). `set` stores any
// value a real field can hold (validate() names it later when out of range);
// for an integer or choice field it throws InvalidOption (check_option's
// message) when the value has no such integer (NaN, infinite, beyond the
// field's type, a choice past the last), where a cast would be undefined.
template <typename Options>
struct OptionEntry : OptionInfo {
  std::function<double(const Options&)> get;
  std::function<void(Options&, double)> set;
};

// True when `value` is allowed (NaN never is).
bool accepts(const OptionInfo& option, double value);

// "in [1, 20]", "> 0 (inf = off)", "0 (off) or in [0.01, 10]", "on or off", "grow or shrink".
std::string range_text(const OptionInfo& option);

// A value as the catalogue writes it: "inf", "on"/"off", the choice's name, or the number.
std::string value_text(const OptionInfo& option, double value);

// Throws InvalidOption(option.name, "<name> must be <range>, got <value>") unless accepted.
void check_option(const OptionInfo& option, double value);

// The value `value` of `option` as the integer type T of its field (an
// integral or enumeration type); throws InvalidOption (check_option's
// message) when T has no such value, or for an enumeration when the value is
// outside [option.lo, option.hi]. Used by the catalogues' setters.
template <typename T>
T integer_field_value(const OptionInfo& option, double value) {
  bool fits;
  if constexpr (std::is_enum_v<T>) {
    fits = value >= option.lo && value <= option.hi;
  } else {
    // lowest() and max() + 1 are powers of two (or 0), exact as doubles.
    const double lo = static_cast<double>(std::numeric_limits<T>::lowest());
    const double past_max = static_cast<double>(std::numeric_limits<T>::max() / 2 + 1) * 2.0;
    fits = value >= lo && value < past_max;
  }
  if (!fits) {
    check_option(option, value);
    throw InvalidOption(option.name, option.name + " must be " + range_text(option) + ", got a value its field cannot hold");
  }
  if constexpr (std::is_enum_v<T>) return static_cast<T>(static_cast<std::underlying_type_t<T>>(value));
  else return static_cast<T>(value);
}

// The options of gdm::deform, in the order of DeformOptions.
const std::vector<OptionEntry<DeformOptions>>& deform_option_catalogue();

// The same entries reaching DeformOptions inside a larger struct (e.g.
// PipelineOptions::deform), for a front end's own catalogue.
template <typename Outer>
std::vector<OptionEntry<Outer>> lift_options(DeformOptions Outer::*member) {
  std::vector<OptionEntry<Outer>> out;
  for (const auto& e : deform_option_catalogue()) {
    OptionEntry<Outer> o;
    static_cast<OptionInfo&>(o) = e;
    o.get = [get = e.get, member](const Outer& x) { return get(x.*member); };
    o.set = [set = e.set, member](Outer& x, double v) { set(x.*member, v); };
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace gdm
