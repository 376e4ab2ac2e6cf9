#pragma once
// Declared parameters: the schema a layer declares for its settings (ParamSpec, one per key) and
// the typed values read against it (ParamValues: int, real, a choice's name or a bool, keyed by
// name). Every layer declares its own here -- a strategy's renders[] parameters (tracer/), the
// config sections (passes/snapshot_params.h, tracer/shading_params.h, eval/config_schema.h) --
// and the readers, --set keys, --help lines and docs tables are generated from the one list.
// No YAML here: the config reader turns its nodes into these values.
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace aamap {

enum class ParamType { Int, Real, Choice, Bool };
const char* toString(ParamType type);  // "int", "real", "choice", "bool"

// int, real, a choice's name, or a bool.
using ParamValue = std::variant<int, double, std::string, bool>;
// Integers as integers, other reals as %g, a choice as its name, a bool as true/false.
std::string formatNumber(double value);
std::string toString(const ParamValue& value);

struct ParamSpec {
    std::string name;  // the YAML key inside its mapping (renders[], snapshot, ...)
    ParamType type = ParamType::Real;
    double lo = 0, hi = 0;  // Int, Real: the range (hi may be infinity), inclusive unless openLo
    double defaultValue = 0;  // Int, Real; Bool: 0 or 1
    std::vector<std::string> choices;  // Choice: the names; the first is the default
    std::string doc;
    bool openLo = false;  // Real: lo itself is excluded (an exposure > 0)

    ParamValue defaultParam() const;
    // The value as this parameter's type, or nullopt with `error` set: an int for a real is
    // widened, an integral real for an int narrowed; out of range and unknown names are errors.
    std::optional<ParamValue> check(const ParamValue& value, std::string& error) const;
    // The nearest valid value: numbers clamped into the range, an unknown choice the default.
    ParamValue clamp(const ParamValue& value) const;
    std::string rangeText() const;  // "[1, 64]", "(0, 1]", "paper/linear-rays", "true/false"
    // "spacing int in [1, 64] (8)", "mapping paper/linear-rays (paper)"; markdown: names in backticks.
    std::string summary(bool markdown) const;
};

ParamSpec intParam(std::string name, int lo, int hi, int fallback, std::string doc);
ParamSpec realParam(std::string name, double lo, double hi, double fallback, std::string doc);
// A real in (lo, hi]: lo itself is not a valid value.
ParamSpec realParamAbove(std::string name, double lo, double hi, double fallback, std::string doc);
ParamSpec choiceParam(std::string name, std::vector<std::string> choices, std::string doc);
ParamSpec boolParam(std::string name, bool fallback, std::string doc);

// The spec named `name` in `specs`, or null.
const ParamSpec* findParam(const std::vector<ParamSpec>& specs, const std::string& name);

// Values keyed by name, in the order first set.
class ParamValues {
public:
    ParamValues() = default;
    ParamValues(std::initializer_list<std::pair<std::string, ParamValue>> values);

    ParamValues& set(const std::string& name, ParamValue value);  // replaces an earlier value
    const ParamValue* find(const std::string& name) const;         // null when not set
    bool has(const std::string& name) const { return find(name) != nullptr; }
    // Typed reads; throw std::invalid_argument when the name is missing or holds another type.
    int integer(const std::string& name) const;
    double real(const std::string& name) const;
    const std::string& choice(const std::string& name) const;
    bool boolean(const std::string& name) const;

    const std::vector<std::pair<std::string, ParamValue>>& entries() const { return values_; }
    bool empty() const { return values_.empty(); }
    bool operator==(const ParamValues&) const = default;

private:
    const ParamValue& at(const std::string& name) const;
    std::vector<std::pair<std::string, ParamValue>> values_;
};

}  // namespace aamap
