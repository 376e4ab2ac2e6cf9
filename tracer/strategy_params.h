#pragma once
// A strategy's parameters: the schema a strategy declares (ParamSpec, one per parameter) and the
// typed values a render hands it (StrategyParams: int, real or a choice's name, keyed by name).
// The one place where a value is checked against its range, for the config, --set, the viewer
// and the tracer alike. No YAML here: the config reader turns its nodes into these values.
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace aamap {

enum class ParamType { Int, Real, Choice };
const char* toString(ParamType type);  // "int", "real", "choice"

// int, real, or a choice's name.
using ParamValue = std::variant<int, double, std::string>;
// Integers as integers, other reals as %g, a choice as its name (render names, series, --help).
std::string formatNumber(double value);
std::string toString(const ParamValue& value);

struct ParamSpec {
    std::string name;  // the YAML key inside renders[] (a list value sweeps it)
    ParamType type = ParamType::Real;
    double lo = 0, hi = 0;  // Int, Real: the inclusive range (hi may be infinity)
    double defaultValue = 0;  // Int, Real
    std::vector<std::string> choices;  // Choice: the names; the first is the default
    std::string doc;

    ParamValue defaultParam() const;
    // The value as this parameter's type, or nullopt with `error` set: an int for a real is
    // widened, an integral real for an int narrowed; out of range and unknown names are errors.
    std::optional<ParamValue> check(const ParamValue& value, std::string& error) const;
    // The nearest valid value: numbers clamped into the range, an unknown choice the default.
    ParamValue clamp(const ParamValue& value) const;
    std::string rangeText() const;  // "[1, 64]", "paper/linear-rays"
    // "spacing int in [1, 64] (8)", "mapping paper/linear-rays (paper)"; markdown: names in backticks.
    std::string summary(bool markdown) const;
};

ParamSpec intParam(std::string name, int lo, int hi, int fallback, std::string doc);
ParamSpec realParam(std::string name, double lo, double hi, double fallback, std::string doc);
ParamSpec choiceParam(std::string name, std::vector<std::string> choices, std::string doc);

// Values keyed by name, in the order first set.
class StrategyParams {
public:
    StrategyParams() = default;
    StrategyParams(std::initializer_list<std::pair<std::string, ParamValue>> values);

    StrategyParams& set(const std::string& name, ParamValue value);  // replaces an earlier value
    const ParamValue* find(const std::string& name) const;           // null when not set
    bool has(const std::string& name) const { return find(name) != nullptr; }
    // Typed reads; throw std::invalid_argument when the name is missing or holds another type.
    int integer(const std::string& name) const;
    double real(const std::string& name) const;
    const std::string& choice(const std::string& name) const;

    const std::vector<std::pair<std::string, ParamValue>>& entries() const { return values_; }
    bool empty() const { return values_.empty(); }
    bool operator==(const StrategyParams&) const = default;

private:
    const ParamValue& at(const std::string& name) const;
    std::vector<std::pair<std::string, ParamValue>> values_;
};

}  // namespace aamap
