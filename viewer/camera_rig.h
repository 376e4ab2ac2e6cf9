#pragma once
// Orbit and fly camera over a View: orbit turns around a pivot in front of the camera, fly moves
// the camera and the pivot together. Field of view and shift stay those of the config's view, so
// the first frame is exactly the offline render's view. No GLFW here: the viewer maps input to it.
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace aamap {

class CameraRig {
public:
    // pivotDistance: how far in front of the camera orbiting turns (the scene's centre, say).
    CameraRig(const View& start, float pivotDistance);

    void orbit(float yawRadians, float pitchRadians);  // around the pivot, about the view's up
    void look(float yawRadians, float pitchRadians);   // turn in place (fly), the pivot follows
    void dolly(float fraction);                        // towards the pivot by fraction of its distance
    void fly(const glm::vec3& local);                  // (right, up, forward) in units of the pivot distance
    void reset() { *this = CameraRig(start_, startDistance_); }

    View view() const;
    bool atStart() const;  // exactly the config's view (a reference file matches it only there)

private:
    void setDirection(const glm::vec3& forward);

    View start_;
    float startDistance_;
    glm::vec3 position_, forward_, worldUp_;
    float distance_;
};

// Distance from the view's position to the centre of the scene's bounding box, along the view
// direction (at least a small positive value): a natural orbit pivot.
float pivotDistanceFor(const Scene& scene, const View& view);

}  // namespace aamap
