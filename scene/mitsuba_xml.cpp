#include "scene/mitsuba_xml.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <pugixml.hpp>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "scene/spectrum.h"
#include "scene/text_util.h"

namespace aamap::mitsuba {
namespace fs = std::filesystem;

namespace {

constexpr int kMaxIncludeDepth = 32;
constexpr int kMaxElementDepth = 256;  // a hostile file must not recurse without bound

// Byte offset -> 1-based line, from the start of each line.
class LineTable {
public:
    explicit LineTable(std::string_view text) {
        starts_.push_back(0);
        for (std::size_t i = 0; i < text.size(); ++i)
            if (text[i] == '\n') starts_.push_back(i + 1);
    }
    int line(std::ptrdiff_t offset) const {
        if (offset < 0) return 0;
        const auto it = std::upper_bound(starts_.begin(), starts_.end(), static_cast<std::size_t>(offset));
        return static_cast<int>(it - starts_.begin());
    }

private:
    std::vector<std::size_t> starts_;
};

class Reader {
public:
    explicit Reader(std::map<std::string, std::string> parameters) : parameters_(std::move(parameters)) {}

    // The children of one file's <scene>, appended to `out`.
    void readFile(const fs::path& file, std::string_view text, std::vector<Element>& out, int* version,
                  const Element* includedFrom) {
        const fs::path canonical = fs::weakly_canonical(file);
        if (std::find(stack_.begin(), stack_.end(), canonical) != stack_.end()) {
            fail(*includedFrom, fmt::format("include cycle: '{}' includes itself (through {} file(s))", file.string(),
                                            stack_.size()));
        }
        if (stack_.size() >= kMaxIncludeDepth) fail(*includedFrom, "includes nest too deeply");
        stack_.push_back(canonical);
        pugi::xml_document doc;
        const pugi::xml_parse_result result =
            doc.load_buffer(text.data(), text.size(), pugi::parse_default | pugi::parse_ws_pcdata_single);
        const LineTable lines(text);
        if (!result) throw InputError(file, lines.line(result.offset), 0, fmt::format("malformed XML: {}", result.description()));
        const pugi::xml_node root = doc.document_element();
        if (std::string_view(root.name()) != "scene") {
            throw InputError(file, lines.line(root.offset_debug()), 0,
                             fmt::format("the root element is <{}>; a Mitsuba scene file starts with <scene>", root.name()));
        }
        if (version != nullptr) *version = parseVersion(file, lines.line(root.offset_debug()), root.attribute("version").value());
        for (const pugi::xml_node child : root.children()) {
            if (child.type() != pugi::node_element) continue;
            readElement(child, file, lines, out, 0);
        }
        stack_.pop_back();
    }

private:
    static int parseVersion(const fs::path& file, int line, std::string_view version) {
        if (version.empty()) throw InputError(file, line, 0, "<scene> has no version attribute (0.5.0, 2.0.0 or 3.0.0)");
        const auto major = text::parseInteger(version.substr(0, version.find('.')));
        if (!major || *major < 0 || *major > 3)
            throw InputError(file, line, 0, fmt::format("unsupported scene version '{}' (0.5/0.6, 2.x or 3.x)", version));
        return static_cast<int>(*major == 1 ? 0 : *major);
    }

    void readElement(const pugi::xml_node node, const fs::path& file, const LineTable& lines, std::vector<Element>& out,
                     int depth) {
        Element e;
        e.tag = node.name();
        e.file = file;
        e.line = lines.line(node.offset_debug());
        if (depth > kMaxElementDepth) fail(e, "elements nest too deeply");
        for (const pugi::xml_attribute a : node.attributes()) {
            std::string value = substitute(e, a.value());
            const std::string key = a.name();
            if (key == "name") value = snakeCase(value);
            e.attributes[key] = std::move(value);
        }
        if (e.tag == "default") {
            const std::string name = e.attribute("name"), value = e.attribute("value");
            if (name.empty() || !e.has("value")) fail(e, "<default> needs name and value attributes");
            // Substitution normalised "name" to snake_case; parameters keep the spelling as written.
            parameters_.try_emplace(node.attribute("name").value(), value);
            return;
        }
        if (e.tag == "include") {
            const std::string name = e.attribute("filename");
            if (name.empty()) fail(e, "<include> needs a filename attribute");
            const fs::path path = fs::path(name).is_absolute() ? fs::path(name) : file.parent_path() / name;
            std::error_code ec;
            if (!fs::is_regular_file(path, ec)) fail(e, fmt::format("included file '{}' not found", path.string()));
            std::ifstream in(path, std::ios::binary);
            std::ostringstream buffer;
            buffer << in.rdbuf();
            if (!in) fail(e, fmt::format("cannot read included file '{}'", path.string()));
            readFile(path, buffer.str(), out, nullptr, &e);
            return;
        }
        for (const pugi::xml_node child : node.children()) {
            if (child.type() != pugi::node_element) continue;
            readElement(child, file, lines, e.children, depth + 1);
        }
        out.push_back(std::move(e));
    }

    // $name -> its parameter's value; an undefined name is an error.
    std::string substitute(const Element& at, std::string_view value) const {
        std::string out;
        for (std::size_t i = 0; i < value.size(); ++i) {
            if (value[i] != '$') {
                out += value[i];
                continue;
            }
            std::size_t end = i + 1;
            while (end < value.size() && (std::isalnum(static_cast<unsigned char>(value[end])) || value[end] == '_')) ++end;
            const std::string name(value.substr(i + 1, end - i - 1));
            if (name.empty()) fail(at, fmt::format("'$' without a parameter name in '{}'", value));
            const auto it = parameters_.find(name);
            if (it == parameters_.end())
                fail(at, fmt::format("parameter '${}' is not defined (add <default name=\"{}\" value=\"...\"/>)", name, name));
            out += it->second;
            i = end - 1;
        }
        return out;
    }

    std::map<std::string, std::string> parameters_;
    std::vector<fs::path> stack_;  // the files being read, for cycles
};

void indexElement(const Element& e, std::map<std::string, const Element*>& byId) {
    // A <ref> names an id; only definitions are indexed.
    if (e.tag != "ref" && e.has("id")) {
        const auto [it, inserted] = byId.emplace(e.id(), &e);
        if (!inserted)
            fail(e, fmt::format("id '{}' is already used at {}:{}", e.id(), it->second->file.string(), it->second->line));
    }
    for (const Element& c : e.children) indexElement(c, byId);
}

}  // namespace

std::string Element::attribute(std::string_view key) const {
    const auto it = attributes.find(std::string(key));
    return it == attributes.end() ? std::string() : it->second;
}

std::string Element::location() const { return fmt::format("{}:{}", file.string(), line); }

const Element* Element::property(std::string_view propertyName) const {
    for (const Element& c : children)
        if (c.name() == propertyName) return &c;
    return nullptr;
}

void Document::index() {
    byId.clear();
    indexElement(root, byId);
}

void fail(const Element& at, const std::string& problem) { throw InputError(at.file, at.line, 0, problem); }

Document parseDocument(std::string_view text, const fs::path& file, std::map<std::string, std::string> parameters) {
    Document doc;
    doc.root.tag = "scene";
    doc.root.file = file;
    doc.root.line = 1;
    Reader(std::move(parameters)).readFile(file, text, doc.root.children, &doc.majorVersion, nullptr);
    doc.index();
    return doc;
}

Document readDocument(const fs::path& file, std::map<std::string, std::string> parameters) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) throw InputError(file, "Mitsuba scene file not found");
    std::ifstream in(file, std::ios::binary);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (!in) throw InputError(file, "cannot read Mitsuba scene file");
    return parseDocument(buffer.str(), file, std::move(parameters));
}

std::string snakeCase(std::string_view name) {
    std::string out;
    for (std::size_t i = 0; i < name.size(); ++i) {
        const char c = name[i];
        const bool upper = c >= 'A' && c <= 'Z';
        if (upper && i > 0) {
            const char prev = name[i - 1];
            if ((prev >= 'a' && prev <= 'z') || (prev >= '0' && prev <= '9')) out += '_';
        }
        out += upper ? static_cast<char>(c - 'A' + 'a') : c;
    }
    return out;
}

void Warnings::once(const std::string& kind, const std::string& message) {
    if (!kinds_.insert(kind).second) return;
    spdlog::warn("{}", message);
    messages_.push_back(message);
}

std::vector<double> parseNumbers(const Element& at, const std::string& text) {
    std::vector<double> out;
    std::string token;
    const auto flush = [&] {
        if (token.empty()) return;
        const auto v = text::parseNumber(token);
        if (!v || !std::isfinite(*v)) fail(at, fmt::format("'{}' is not a finite number", token));
        out.push_back(*v);
        token.clear();
    };
    for (char c : text) {
        if (c == ',' || text::isBlank(c) || c == '\n') flush();
        else token += c;
    }
    flush();
    return out;
}

namespace {

const Element* typed(const Element& parent, std::string_view name, std::initializer_list<std::string_view> tags) {
    const Element* p = parent.property(name);
    if (p == nullptr) return nullptr;
    if (std::find(tags.begin(), tags.end(), p->tag) == tags.end()) {
        std::string list;
        for (std::string_view t : tags) list += (list.empty() ? "<" : ", <") + std::string(t) + ">";
        fail(*p, fmt::format("property '{}' is a <{}>; expected {}", name, p->tag, list));
    }
    if (!p->has("value")) fail(*p, fmt::format("<{} name=\"{}\"> has no value attribute", p->tag, name));
    return p;
}

double oneNumber(const Element& p) {
    const std::vector<double> v = parseNumbers(p, p.attribute("value"));
    if (v.size() != 1) fail(p, fmt::format("'{}' should be one number", p.attribute("value")));
    return v[0];
}

float srgbToLinear(double v) {
    return static_cast<float>(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
}

}  // namespace

float floatProperty(const Element& parent, std::string_view name, float fallback) {
    const Element* p = typed(parent, name, {"float", "integer"});
    if (p == nullptr) return fallback;
    const double v = oneNumber(*p);
    if (std::abs(v) > 3.0e38) fail(*p, fmt::format("{} is out of range", v));
    return static_cast<float>(v);
}

int integerProperty(const Element& parent, std::string_view name, int fallback) {
    const Element* p = typed(parent, name, {"integer"});
    if (p == nullptr) return fallback;
    const auto v = text::parseInteger(std::string(text::trim(p->attribute("value"))));
    if (!v || *v < -(1LL << 31) || *v >= (1LL << 31)) fail(*p, fmt::format("'{}' is not an integer", p->attribute("value")));
    return static_cast<int>(*v);
}

bool booleanProperty(const Element& parent, std::string_view name, bool fallback) {
    const Element* p = typed(parent, name, {"boolean"});
    if (p == nullptr) return fallback;
    const std::string v = text::toLower(p->attribute("value"));
    if (v == "true") return true;
    if (v == "false") return false;
    fail(*p, fmt::format("'{}' is not true or false", p->attribute("value")));
}

std::string stringProperty(const Element& parent, std::string_view name, const std::string& fallback) {
    const Element* p = typed(parent, name, {"string"});
    return p == nullptr ? fallback : p->attribute("value");
}

glm::vec3 pointProperty(const Element& parent, std::string_view name, glm::vec3 fallback) {
    const Element* p = parent.property(name);
    if (p == nullptr) return fallback;
    if (p->tag != "point" && p->tag != "vector") fail(*p, fmt::format("property '{}' should be a <point> or <vector>", name));
    if (p->has("value")) {
        const std::vector<double> v = parseNumbers(*p, p->attribute("value"));
        if (v.size() != 3) fail(*p, fmt::format("'{}' should be three numbers", p->attribute("value")));
        return glm::vec3(v[0], v[1], v[2]);
    }
    glm::vec3 out(0.0f);
    const char* axes[] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        if (!p->has(axes[i])) continue;
        const std::vector<double> v = parseNumbers(*p, p->attribute(axes[i]));
        if (v.size() != 1) fail(*p, fmt::format("{}='{}' should be one number", axes[i], p->attribute(axes[i])));
        out[i] = static_cast<float>(v[0]);
    }
    return out;
}

glm::vec3 colourProperty(const Element& parent, std::string_view name, glm::vec3 fallback, Warnings& warnings,
                         SpectrumUse use) {
    const Element* p = parent.property(name);
    if (p == nullptr) return fallback;
    if (p->tag == "float") return glm::vec3(static_cast<float>(oneNumber(*p)));
    if (p->tag == "rgb" || p->tag == "srgb") {
        if (!p->has("value")) fail(*p, fmt::format("<{}> has no value attribute", p->tag));
        const std::string text = p->attribute("value");
        std::vector<double> v;
        if (text.starts_with("#") && text.size() == 7) {  // "#rrggbb", an sRGB hex colour
            for (int i = 0; i < 3; ++i) {
                const auto byte = std::strtol(text.substr(1 + 2 * i, 2).c_str(), nullptr, 16);
                v.push_back(static_cast<double>(byte) / 255.0);
            }
        } else {
            v = parseNumbers(*p, text);
        }
        if (v.size() == 1) v = {v[0], v[0], v[0]};
        if (v.size() != 3) fail(*p, fmt::format("<{}> '{}' should be one or three numbers", p->tag, text));
        if (p->tag == "srgb" || text.starts_with("#")) return {srgbToLinear(v[0]), srgbToLinear(v[1]), srgbToLinear(v[2])};
        return glm::vec3(v[0], v[1], v[2]);
    }
    if (p->tag == "spectrum") {
        if (p->has("filename")) fail(*p, "spectra from files are not supported; give wavelength:value pairs or an <rgb>");
        if (!p->has("value")) fail(*p, "<spectrum> has no value attribute");
        const std::string text = p->attribute("value");
        if (text.find(':') == std::string::npos) return glm::vec3(static_cast<float>(oneNumber(*p)));
        std::vector<std::pair<double, double>> samples;
        std::stringstream entries(text);
        for (std::string entry; std::getline(entries, entry, ',');) {
            const auto colon = entry.find(':');
            const auto nm = text::parseNumber(text::trim(entry.substr(0, colon)));
            const auto value = colon == std::string::npos ? std::nullopt : text::parseNumber(text::trim(entry.substr(colon + 1)));
            if (!nm || !value || !std::isfinite(*nm) || !std::isfinite(*value))
                fail(*p, fmt::format("spectrum entry '{}' is not wavelength:value", std::string(text::trim(entry))));
            samples.emplace_back(*nm, *value);
        }
        warnings.once("spectrum", fmt::format("{}:{}: sampled spectra are converted to linear RGB (CIE 1931 projection)",
                                              p->file.string(), p->line));
        return spectrumToRgb(std::move(samples), use);
    }
    if (p->tag == "blackbody") fail(*p, "<blackbody> spectra are not supported; give an <rgb>");
    fail(*p, fmt::format("property '{}' is a <{}>; expected a colour (<rgb>, <srgb>, <spectrum> or <float>)", name, p->tag));
}

}  // namespace aamap::mitsuba
