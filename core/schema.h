#pragma once
// A config section's schema bound to the struct that holds it: each key declared once, with the
// field it fills, its type, range, default and doc, and for a choice the enum value of each name.
//
//   Schema<SnapshotSettings> s;
//   s.field(&SnapshotSettings::scale, "scale", in(1.0, 4.0), 1.5, "snapshot resolution / render ...")
//    .choice(&SnapshotSettings::map, "map", {{"luminance", AamapSource::Luminance}, ...}, "...");
//
// From the one list come the struct's defaults (setDefaults, called by the struct's constructor),
// the ParamSpecs the readers, --set keys, --help lines, CLI options and docs tables are generated
// from (specs()), the typed values of a struct (values(), changed()) and the struct filled from
// checked values (fill()). No YAML or JSON here: eval/config_schema.h walks it for those.
#include <charconv>
#include <cstddef>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/params.h"

namespace aamap {

// An int or real key's range: [lo, hi], or (lo, hi] with above().
struct ParamRange {
    double lo = 0, hi = 0;
    bool openLo = false;
};
inline ParamRange in(double lo, double hi) { return {lo, hi, false}; }
inline ParamRange above(double lo, double hi) { return {lo, hi, true}; }

// A float as the double its shortest decimal spells (0.2f -> 0.2, not 0.200000003): a float field
// then reads back the value the user wrote and equals its default in cache keys and JSON.
inline double shortestDouble(float f) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof(text), f).ptr;
    double d = 0.0;
    std::from_chars(text, end, d);
    return d;
}

template <class T>
class Schema {
public:
    struct Field {
        ParamSpec spec;
        std::function<ParamValue(const T&)> get;
        std::function<void(T&, const ParamValue&)> set;  // a value spec.check() accepted
    };

    // An int or real member.
    template <class M>
        requires(std::is_arithmetic_v<M> && !std::is_same_v<M, bool>)
    Schema& field(M T::*member, std::string name, ParamRange range, std::type_identity_t<M> fallback, std::string doc) {
        ParamSpec spec;
        spec.name = std::move(name);
        spec.type = std::is_integral_v<M> ? ParamType::Int : ParamType::Real;
        spec.lo = range.lo;
        spec.hi = range.hi;
        spec.openLo = range.openLo;
        // A float field's default as the float holds it, so that the default reads back equal.
        if constexpr (std::is_same_v<M, float>) spec.defaultValue = shortestDouble(fallback);
        else spec.defaultValue = static_cast<double>(fallback);
        spec.doc = std::move(doc);
        add({std::move(spec),
             [member](const T& t) -> ParamValue {
                 if constexpr (std::is_integral_v<M>) return static_cast<int>(t.*member);
                 else if constexpr (std::is_same_v<M, float>) return shortestDouble(t.*member);
                 else return static_cast<double>(t.*member);
             },
             [member, range](T& t, const ParamValue& v) {
                 if constexpr (std::is_integral_v<M>) {
                     t.*member = static_cast<M>(std::get<int>(v));
                 } else {
                     M m = static_cast<M>(std::holds_alternative<int>(v) ? std::get<int>(v) : std::get<double>(v));
                     // A value just above an open lower end may round onto it in a float: take the
                     // float just above it instead, so the field stays inside the declared range.
                     if (range.openLo && !(m > static_cast<M>(range.lo)))
                         m = std::nextafter(static_cast<M>(range.lo), std::numeric_limits<M>::infinity());
                     t.*member = m;
                 }
             }});
        return *this;
    }

    // A bool member.
    Schema& field(bool T::*member, std::string name, bool fallback, std::string doc) {
        add({boolParam(std::move(name), fallback, std::move(doc)),
             [member](const T& t) -> ParamValue { return t.*member; },
             [member](T& t, const ParamValue& v) { t.*member = std::get<bool>(v); }});
        return *this;
    }

    // A choice: the names and the value each stands for; the first is the default.
    template <class E>
    Schema& choice(E T::*member, std::string name, std::vector<std::pair<std::string, E>> names, std::string doc) {
        std::vector<std::string> choices;
        for (const auto& n : names) choices.push_back(n.first);
        add({choiceParam(std::move(name), std::move(choices), std::move(doc)),
             [member, names](const T& t) -> ParamValue {
                 for (const auto& n : names)
                     if (n.second == t.*member) return n.first;
                 return names.front().first;
             },
             [member, names](T& t, const ParamValue& v) {
                 const std::string& s = std::get<std::string>(v);
                 for (const auto& n : names)
                     if (n.first == s) t.*member = n.second;
             }});
        return *this;
    }

    // Every key of `inner`, the schema of member `member`, as keys of this one (the pixel filter's
    // keys in the image section): one declaration, owned by the layer whose struct it is.
    template <class M>
    Schema& include(M T::*member, const Schema<M>& inner) {
        for (const auto& f : inner.fields())
            add({f.spec, [member, get = f.get](const T& t) { return get(t.*member); },
                 [member, set = f.set](T& t, const ParamValue& v) { set(t.*member, v); }});
        return *this;
    }

    const std::vector<Field>& fields() const { return fields_; }
    // The specs in declaration order (what readSection, --help and the docs walk).
    const std::vector<ParamSpec>& specs() const { return specs_; }
    const Field* find(const std::string& name) const {
        for (const Field& f : fields_)
            if (f.spec.name == name) return &f;
        return nullptr;
    }

    void setDefaults(T& t) const {
        for (const Field& f : fields_) f.set(t, f.spec.defaultParam());
    }
    // Every declared key present in `values` (checked values, as readSection returns them).
    void fill(T& t, const ParamValues& values) const {
        for (const Field& f : fields_)
            if (const ParamValue* v = values.find(f.spec.name)) f.set(t, *v);
    }
    // One key by name from a value of its type; throws std::invalid_argument for an unknown key
    // or a value its spec rejects.
    void set(T& t, const std::string& name, const ParamValue& value) const {
        const Field* f = find(name);
        if (f == nullptr) throw std::invalid_argument("unknown key '" + name + "'");
        std::string error;
        const auto checked = f->spec.check(value, error);
        if (!checked) throw std::invalid_argument(name + ": " + error);
        f->set(t, *checked);
    }
    // Every key's value, in declaration order.
    ParamValues values(const T& t) const {
        ParamValues out;
        for (const Field& f : fields_) out.set(f.spec.name, f.get(t));
        return out;
    }
    // The keys whose value is not the default (what a cache key holds).
    ParamValues changed(const T& t) const {
        ParamValues out;
        for (const Field& f : fields_) {
            ParamValue v = f.get(t);
            if (!(v == f.spec.defaultParam())) out.set(f.spec.name, std::move(v));
        }
        return out;
    }

private:
    void add(Field f) {
        specs_.push_back(f.spec);
        fields_.push_back(std::move(f));
    }
    std::vector<Field> fields_;
    std::vector<ParamSpec> specs_;
};

}  // namespace aamap
