#pragma once
// Reading Mitsuba scene XML (0.5/0.6 and 2/3.x) into a plain element tree, before any plugin is
// interpreted: pugixml parses each file; <include> splices the included scene's children in place
// (relative to the including file, cycles refused); <default name value> defines a parameter
// unless already given; $name in any attribute value is substituted. Property names are
// normalised to snake_case (0.5's toWorld, fovAxis and intIOR become to_world, fov_axis and
// int_ior) so that the interpreters read one spelling. Every element keeps its file and line
// (pugixml's byte offsets turned into lines) for errors.
//
// Also the typed property readers (float, integer, boolean, string, rgb/srgb/spectrum, point,
// vector), since reading a value is part of reading the XML.
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/spectrum.h"

namespace aamap::mitsuba {

struct Element {
    std::string tag;                                // "shape", "float", "ref", ...
    std::map<std::string, std::string> attributes;  // after substitution; "name" in snake_case
    std::vector<Element> children;
    std::filesystem::path file;
    int line = 0;

    // "" when absent.
    std::string attribute(std::string_view key) const;
    // "file:line", the prefix of every message about this element.
    std::string location() const;
    bool has(std::string_view key) const { return attributes.count(std::string(key)) != 0; }
    std::string type() const { return attribute("type"); }
    std::string name() const { return attribute("name"); }
    std::string id() const { return attribute("id"); }
    // The child property with this name (any tag), or nullptr.
    const Element* property(std::string_view propertyName) const;
};

struct Document {
    Document() = default;
    Document(Document&&) = default;  // byId points into the children, which a move keeps
    Document& operator=(Document&&) = default;
    Document(const Document&) = delete;
    Element root;           // <scene>, includes spliced in
    int majorVersion = 0;   // from <scene version="...">: 0 for 0.5/0.6, 2 or 3
    std::map<std::string, const Element*> byId;  // every element with an id (filled by index())
    void index();           // (re)builds byId; throws InputError for a duplicate id
};

// "file:line: problem" for this element.
[[noreturn]] void fail(const Element& at, const std::string& problem);

// Reads a scene file. `parameters` are given values (as Mitsuba's -D name=value); <default>
// fills the others. Throws InputError (file:line) for malformed XML, a missing or cyclic include,
// an undefined $parameter, or a root that is not <scene>.
Document readDocument(const std::filesystem::path& file, std::map<std::string, std::string> parameters = {});
// The same from text in memory (tests, fuzzing); includes resolve relative to file's folder.
Document parseDocument(std::string_view text, const std::filesystem::path& file,
                       std::map<std::string, std::string> parameters = {});

// camelCase -> snake_case ("toWorld" -> "to_world", "intIOR" -> "int_ior"); snake_case unchanged.
std::string snakeCase(std::string_view name);

// One warning per kind of approximation, however many elements need it; every message is also
// kept for callers and tests.
class Warnings {
public:
    void once(const std::string& kind, const std::string& message);
    const std::vector<std::string>& messages() const { return messages_; }

private:
    std::set<std::string> kinds_;
    std::vector<std::string> messages_;
};

// Typed property readers. Each returns `fallback` when the property is absent and throws
// InputError (file:line) when it is present but malformed or of the wrong kind.
float floatProperty(const Element& parent, std::string_view name, float fallback);
int integerProperty(const Element& parent, std::string_view name, int fallback);
bool booleanProperty(const Element& parent, std::string_view name, bool fallback);
std::string stringProperty(const Element& parent, std::string_view name, const std::string& fallback);
// <point>/<vector> with x y z attributes or value="x, y, z".
glm::vec3 pointProperty(const Element& parent, std::string_view name, glm::vec3 fallback);
// A constant colour: <rgb>, <srgb> (decoded to linear), <spectrum> (a constant, or
// wavelength:value pairs converted to linear RGB, see scene/spectrum.h), <float> (grey).
// A <texture> or a <ref> property is not a constant: callers that accept textures look first.
// `use`: how a sampled spectrum is projected (an emitter's radiance, intensity or irradiance is
// Emission).
glm::vec3 colourProperty(const Element& parent, std::string_view name, glm::vec3 fallback, Warnings& warnings,
                         SpectrumUse use = SpectrumUse::Reflectance);
// Numbers in a value attribute, separated by commas and/or blanks.
std::vector<double> parseNumbers(const Element& at, const std::string& text);

}  // namespace aamap::mitsuba
