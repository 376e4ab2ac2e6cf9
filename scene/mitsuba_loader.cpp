#include "scene/mitsuba_loader.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "scene/lights.h"
#include "scene/mitsuba_emitters.h"
#include "scene/mitsuba_materials.h"
#include "scene/mitsuba_shapes.h"
#include "scene/mitsuba_transform.h"
#include "scene/mitsuba_xml.h"

namespace aamap {
namespace fs = std::filesystem;
using namespace mitsuba;

namespace {

constexpr int kMaxInstanceDepth = 8;  // instances of groups are flat in Mitsuba; a cycle must end

class SceneBuilder {
public:
    SceneBuilder(const Document& doc, Scene& scene) : doc_(doc), scene_(scene), materials_(doc, scene, warnings_) {}

    void build() {
        for (const Element& e : doc_.root.children) {
            if (e.tag == "shape") addShape(e, glm::mat4(1.0f), 0);
            else if (e.tag == "emitter") addEmitter(e, scene_, warnings_);
            else if (e.tag == "sensor") addSensor(e, scene_, warnings_);
            else if (e.tag == "medium") ignoreMedium(e);
            else if (e.tag == "bsdf" || e.tag == "texture") {
                if (e.id().empty()) fail(e, fmt::format("a top-level <{}> needs an id for shapes to <ref> it", e.tag));
            } else if (e.tag == "integrator") {
                readIntegrator(e, 0);
            } else if (e.tag == "sampler" || e.tag == "film" || e.tag == "rfilter") {
                spdlog::debug("{}:{}: a top-level <{}> is not read (a sensor's is)", e.file.string(), e.line, e.tag);
            } else {
                fail(e, fmt::format("unexpected <{}> in <scene>", e.tag));
            }
        }
        scene_.areaLights = buildAreaLights(scene_, objectNames_);
    }

    std::vector<std::string> warnings() const { return warnings_.messages(); }
    std::size_t degenerate() const { return degenerate_; }

private:
    // The path-tracing settings of the first integrator that has them: a wrapper (aov, moment,
    // stokes) holds the one that renders. Mitsuba's defaults apply to what the file leaves out.
    void readIntegrator(const Element& e, int depth) {
        SceneRenderSettings& r = scene_.render;
        if (!r.integrator.empty()) return;
        const std::string type = e.type();
        for (const Element& c : e.children)
            if (c.tag == "integrator" && depth < kMaxInstanceDepth) readIntegrator(c, depth + 1);
        if (!r.integrator.empty()) return;  // a nested one rendered
        r.integrator = type;
        r.at = e.location();
        r.hideEmitters = booleanProperty(e, "hide_emitters", false);
        if (type == "direct") {
            r.maxDepth = 2;  // emitted and direct light: a path of two segments
            return;
        }
        const int maxDepth = integerProperty(e, "max_depth", -1);
        if (maxDepth < -1 || maxDepth == 0)
            fail(e, fmt::format("max_depth {} is not -1 (unlimited) or a positive depth", maxDepth));
        if (maxDepth > 0) r.maxDepth = maxDepth;
        const int rrDepth = integerProperty(e, "rr_depth", 5);
        if (rrDepth < 1) fail(e, fmt::format("rr_depth {} is not positive", rrDepth));
        r.rrDepth = rrDepth;
    }

    void ignoreMedium(const Element& e) {
        warnings_.once("medium", fmt::format("{}:{}: participating media are ignored", e.file.string(), e.line));
    }

    void addShape(const Element& shape, const glm::mat4& parent, int depth) {
        const std::string type = shape.type();
        if (type == "shapegroup") {
            if (depth > 0) fail(shape, "a shapegroup cannot be nested");
            if (shape.id().empty()) fail(shape, "a shapegroup needs an id for instances to <ref> it");
            return;  // placed by instances
        }
        const glm::mat4 toWorld = parent * transformProperty(shape);
        if (type == "instance") {
            if (depth >= kMaxInstanceDepth) fail(shape, "instances nest too deeply (a cycle?)");
            const Element* group = nullptr;
            for (const Element& c : shape.children)
                if (c.tag == "ref" || (c.tag == "shape" && c.type() == "shapegroup")) group = &materials_.resolve(c);
            if (group == nullptr || group->tag != "shape" || group->type() != "shapegroup")
                fail(shape, "an instance needs a <ref id> to a shapegroup");
            for (const Element& c : group->children) {
                if (c.tag == "shape") addShape(c, toWorld, depth + 1);
            }
            return;
        }
        const Element* bsdf = nullptr;
        glm::vec3 radiance(0.0f);
        for (const Element& c : shape.children) {
            if (c.tag == "bsdf") bsdf = &c;
            else if (c.tag == "emitter") radiance = areaRadiance(c, warnings_);
            else if (c.tag == "medium") ignoreMedium(c);
            else if (c.tag == "ref") {
                const Element& target = materials_.resolve(c);
                if (target.tag == "bsdf") bsdf = &target;
                else if (target.tag == "medium") ignoreMedium(target);
                else if (target.tag == "emitter") radiance = areaRadiance(target, warnings_);
                else fail(c, fmt::format("a shape cannot use <{}> '{}'", target.tag, c.id()));
            }
        }
        const ShapeMesh geometry = shapeGeometry(shape, warnings_);
        const std::uint32_t material = materials_.material(bsdf, radiance);
        const auto object = static_cast<std::uint32_t>(objectNames_.size());
        objectNames_.push_back(shape.id().empty() ? fmt::format("{}@{}", type, shape.line) : shape.id());
        appendShape(scene_.mesh, geometry, toWorld, booleanProperty(shape, "flip_normals", false),
                    booleanProperty(shape, "face_normals", false), material, object, degenerate_);
    }

    const Document& doc_;
    Scene& scene_;
    Warnings warnings_;
    MaterialBuilder materials_;
    std::vector<std::string> objectNames_;
    std::size_t degenerate_ = 0;
};

}  // namespace

Scene loadMitsuba(const fs::path& file, MitsubaLoadReport* report, const std::map<std::string, std::string>& parameters) {
    const Document doc = readDocument(file, parameters);
    Scene scene;
    scene.name = file.parent_path().filename().empty() || file.stem() != "scene" ? file.stem().string()
                                                                                  : file.parent_path().filename().string();
    scene.source = file;
    SceneBuilder builder(doc, scene);
    builder.build();
    if (builder.degenerate() > 0)
        spdlog::warn("{}: skipped {} zero-area triangles", file.string(), builder.degenerate());
    if (scene.mesh.triangles.empty()) spdlog::warn("{}: the scene has no triangles", file.string());
    if (report != nullptr) {
        report->warnings = builder.warnings();
        report->degenerateTriangles = builder.degenerate();
    }
    return scene;
}

}  // namespace aamap
