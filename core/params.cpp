#include "core/params.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace aamap {

const char* toString(ParamType type) {
    switch (type) {
        case ParamType::Int: return "int";
        case ParamType::Real: return "real";
        case ParamType::Choice: return "choice";
        case ParamType::Bool: return "bool";
    }
    return "?";
}

std::string formatNumber(double value) {
    if (value == std::floor(value) && std::fabs(value) < 1e15) return fmt::format("{}", static_cast<long long>(value));
    return fmt::format("{:g}", value);
}

std::string toString(const ParamValue& value) {
    if (const int* i = std::get_if<int>(&value)) return fmt::format("{}", *i);
    if (const double* d = std::get_if<double>(&value)) return formatNumber(*d);
    if (const bool* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
    return std::get<std::string>(value);
}

ParamValue ParamSpec::defaultParam() const {
    switch (type) {
        case ParamType::Int: return static_cast<int>(defaultValue);
        case ParamType::Real: return defaultValue;
        case ParamType::Choice: return choices.front();
        case ParamType::Bool: return defaultValue != 0;
    }
    return defaultValue;
}

std::optional<ParamValue> ParamSpec::check(const ParamValue& value, std::string& error) const {
    if (type == ParamType::Choice) {
        const std::string* name = std::get_if<std::string>(&value);
        if (name != nullptr && std::find(choices.begin(), choices.end(), *name) != choices.end()) return *name;
        error = fmt::format("expected one of {}, found {}", fmt::join(choices, ", "),
                            name != nullptr ? "'" + *name + "'" : toString(value));
        return std::nullopt;
    }
    if (type == ParamType::Bool) {
        if (const bool* b = std::get_if<bool>(&value)) return *b;
        error = fmt::format("expected true or false, found {}", toString(value));
        return std::nullopt;
    }
    if (std::holds_alternative<std::string>(value) || std::holds_alternative<bool>(value)) {
        error = fmt::format("expected {}, found '{}'", type == ParamType::Int ? "an integer" : "a number",
                            toString(value));
        return std::nullopt;
    }
    const double v = std::holds_alternative<int>(value) ? std::get<int>(value) : std::get<double>(value);
    if (type == ParamType::Int && v != std::floor(v)) {
        error = fmt::format("expected an integer, found {}", v);
        return std::nullopt;
    }
    if (!(v >= lo && v <= hi) || (openLo && v == lo)) {  // NaN too
        error = fmt::format("{} is out of range {}", v, rangeText());
        return std::nullopt;
    }
    if (type == ParamType::Int) return static_cast<int>(v);
    return v;
}

ParamValue ParamSpec::clamp(const ParamValue& value) const {
    std::string error;
    if (const auto ok = check(value, error)) return *ok;
    if (type == ParamType::Choice || type == ParamType::Bool || std::holds_alternative<std::string>(value) ||
        std::holds_alternative<bool>(value))
        return defaultParam();
    const double v = std::holds_alternative<int>(value) ? std::get<int>(value) : std::get<double>(value);
    // An open lower end has no nearest value; the default is a valid one.
    const double c = std::isnan(v) || (openLo && v <= lo) ? defaultValue : std::clamp(v, lo, hi);
    if (type == ParamType::Int) return static_cast<int>(std::floor(c));
    return c;
}

std::string ParamSpec::rangeText() const {
    if (type == ParamType::Choice) return fmt::format("{}", fmt::join(choices, "/"));
    if (type == ParamType::Bool) return "true/false";
    return fmt::format("{}{}, {}]", openLo ? "(" : "[", lo, hi);
}

std::string ParamSpec::summary(bool markdown) const {
    const std::string q = markdown ? "`" : "";
    if (type == ParamType::Choice) {
        std::vector<std::string> quoted;
        for (const std::string& c : choices) quoted.push_back(q + c + q);
        return fmt::format("{}{}{} {} ({})", q, name, q, fmt::join(quoted, "/"), choices.front());
    }
    if (type == ParamType::Bool) return fmt::format("{}{}{} bool ({})", q, name, q, toString(defaultParam()));
    return fmt::format("{}{}{} {} in {} ({})", q, name, q, toString(type), rangeText(), formatNumber(defaultValue));
}

ParamSpec intParam(std::string name, int lo, int hi, int fallback, std::string doc) {
    return {std::move(name), ParamType::Int, static_cast<double>(lo), static_cast<double>(hi),
            static_cast<double>(fallback), {}, std::move(doc)};
}

ParamSpec realParam(std::string name, double lo, double hi, double fallback, std::string doc) {
    return {std::move(name), ParamType::Real, lo, hi, fallback, {}, std::move(doc)};
}

ParamSpec realParamAbove(std::string name, double lo, double hi, double fallback, std::string doc) {
    ParamSpec p = realParam(std::move(name), lo, hi, fallback, std::move(doc));
    p.openLo = true;
    return p;
}

ParamSpec choiceParam(std::string name, std::vector<std::string> choices, std::string doc) {
    return {std::move(name), ParamType::Choice, 0, 0, 0, std::move(choices), std::move(doc)};
}

ParamSpec boolParam(std::string name, bool fallback, std::string doc) {
    return {std::move(name), ParamType::Bool, 0, 1, fallback ? 1.0 : 0.0, {}, std::move(doc)};
}

const ParamSpec* findParam(const std::vector<ParamSpec>& specs, const std::string& name) {
    for (const ParamSpec& p : specs)
        if (p.name == name) return &p;
    return nullptr;
}

ParamValues::ParamValues(std::initializer_list<std::pair<std::string, ParamValue>> values) {
    for (const auto& [name, value] : values) set(name, value);
}

ParamValues& ParamValues::set(const std::string& name, ParamValue value) {
    for (auto& [k, v] : values_)
        if (k == name) {
            v = std::move(value);
            return *this;
        }
    values_.emplace_back(name, std::move(value));
    return *this;
}

const ParamValue* ParamValues::find(const std::string& name) const {
    for (const auto& [k, v] : values_)
        if (k == name) return &v;
    return nullptr;
}

const ParamValue& ParamValues::at(const std::string& name) const {
    const ParamValue* v = find(name);
    if (v == nullptr) throw std::invalid_argument(fmt::format("no parameter '{}'", name));
    return *v;
}

int ParamValues::integer(const std::string& name) const {
    const ParamValue& v = at(name);
    if (!std::holds_alternative<int>(v)) throw std::invalid_argument(fmt::format("parameter '{}' is not an int", name));
    return std::get<int>(v);
}

double ParamValues::real(const std::string& name) const {
    const ParamValue& v = at(name);
    if (!std::holds_alternative<double>(v))
        throw std::invalid_argument(fmt::format("parameter '{}' is not a real", name));
    return std::get<double>(v);
}

const std::string& ParamValues::choice(const std::string& name) const {
    const ParamValue& v = at(name);
    if (!std::holds_alternative<std::string>(v))
        throw std::invalid_argument(fmt::format("parameter '{}' is not a choice", name));
    return std::get<std::string>(v);
}

bool ParamValues::boolean(const std::string& name) const {
    const ParamValue& v = at(name);
    if (!std::holds_alternative<bool>(v)) throw std::invalid_argument(fmt::format("parameter '{}' is not a bool", name));
    return std::get<bool>(v);
}

}  // namespace aamap
