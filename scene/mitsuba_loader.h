#pragma once
// Mitsuba scene files (scene.xml, versions 0.5/0.6 and 2/3.x) to the scene model. The XML is read
// by scene/mitsuba_xml.h; transforms, shapes, BSDFs, emitters and the sensor are interpreted by
// scene/mitsuba_{transform,shapes,materials,emitters}.h, which list what maps to what.
// Each shape is one object (its id, else "<type>@<line>"); shapes with an area emitter become
// AreaLights. <shape type="shapegroup" id> defines shapes that <shape type="instance"> with a
// <ref id> places (instances are flattened into the mesh). The integrator and sampler are not
// read: the experiment config decides how to render. Participating media are ignored (one
// warning).
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace aamap {

struct MitsubaLoadReport {
    std::vector<std::string> warnings;  // one per kind of approximation, as also logged
    std::size_t degenerateTriangles = 0;
};

// Throws InputError (file:line) for malformed XML, a missing include, mesh or texture map, an
// unknown plugin, an include cycle, or a value it cannot read; nothing is half-loaded.
Scene loadMitsuba(const std::filesystem::path& file, MitsubaLoadReport* report = nullptr,
                  const std::map<std::string, std::string>& parameters = {});

}  // namespace aamap
