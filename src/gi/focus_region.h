// The focus region of gi mode: the part of the scene the camera sees. Photon mapping's
// parameters are lengths and areas; made relative to the whole scene they fail on the scenes
// people render: a room inside a 200 m ground plane (Bitterli's classroom) got density radii of
// metres and one photon in a thousand from the sun. When the camera sees a region much smaller
// than the scene, gi takes its density-estimation radii from that region and aims most
// directional and sky photons at it (a defensive mixture, so the maps stay unbiased:
// gi/photon_emitter.cpp). docs/photon-map.md, "Focus region".
#pragma once

#include "core/math.h"

#include <cstddef>

namespace rayproc {

class EmbreeScene;
struct Scene;

struct FocusRegion {
    Bounds3 bounds;          // the camera's first hits (empty: none)
    std::size_t hits = 0;    // camera rays of the probe grid that hit something
    std::size_t rays = 0;    // probe rays traced
    bool active = false;     // the region is small against the scene: gi focuses on it
    // The first hits and what the probe rays reach past them through mirrors and smooth glass
    // (up to kFocusSpecularBounces): where caustic photons must go to light what the camera
    // sees through water or glass. The first hits alone aim them at the water's surface, and
    // refraction moves them off the floor seen through it: a sun through open water at 30
    // degrees lit only half of such a view with focused photons, the other half with the
    // whole disk's, each a thousand times heavier (fireflies).
    Bounds3 specularBounds;

    // Where focused photons are aimed: the bounds grown by kFocusMargin of their diagonal on
    // every side, so geometry at the edge of the view and just outside it, which lights what
    // is in view, gets its share.
    Bounds3 emissionBounds() const;
    // The same for the caustic pass: specularBounds grown by the same margin.
    Bounds3 causticEmissionBounds() const;
};

// A region whose bounding sphere's radius is at most this fraction of the scene's focuses gi.
inline constexpr float kFocusRadiusFraction = 0.5f;
// Fraction of the camera's hits trimmed at each end of each axis when bounding them.
inline constexpr double kFocusTrim = 0.02;
// The emission bounds' margin, a fraction of the region's diagonal.
inline constexpr float kFocusMargin = 0.25f;
// Specular bounces the probe rays follow for specularBounds.
inline constexpr int kFocusSpecularBounces = 4;
// Share of directional and sky photons aimed at an active focus region; the rest cover the
// whole scene, so light that reaches the region from outside it is still carried.
inline constexpr float kFocusPhotonShare = 0.9f;

// Traces a grid of pinhole camera rays through pixel centres (about `probeRays` of them,
// deterministic) and bounds their first hits (and, for specularBounds, the hits past them along
// mirror reflection and smooth refraction).
FocusRegion cameraFocusRegion(const Scene& scene, const EmbreeScene& accel, int packetWidth,
                              int probeRays = 4096);

} // namespace rayproc
