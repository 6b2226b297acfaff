// The hierarchical scene (Farnsworth & Erbacher, Figure 4): groups ("Sets") with transforms,
// instances that place a shared group again, and shape leaves. Every node has a bounding volume.
// This is the renderer-independent description; accel/ maps it onto Embree.
#pragma once

#include "core/math.h"
#include "scene/emission_spectrum.h"
#include "scene/material.h"
#include "scene/texture.h"

#include <memory>
#include <string>
#include <vector>

namespace rayproc {

struct TriangleMesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals; // empty, or one per position (shading normals)
    std::vector<Vec2> uvs;     // empty, or one per position
    std::vector<std::uint32_t> indices; // 3 per triangle
    std::size_t triangleCount() const { return indices.size() / 3; }
    Bounds3 bounds() const;
};

enum class ShapeType { Mesh, Sphere, Disk };

// A leaf. Geometry is in the space of the enclosing group. Rectangles and quads are meshes of
// two triangles with `isQuad` set, so that preview mode can put a point light at each corner.
struct Shape {
    ShapeType type = ShapeType::Mesh;
    std::string name;
    int material = 0; // index into Scene::materials
    Vec3 emission{0, 0, 0}; // radiance emitted from the front side (and back when twoSided)
    // The emission's own spectrum (a pbrt-v4 blackbody, ...; scene/emission_spectrum.h), which
    // the spectral mode renders; nullptr: the colour's RGB illuminant spectrum.
    EmissionSpectrumRef emissionSpectrum;
    bool twoSided = false;
    // Mesh
    std::shared_ptr<const TriangleMesh> mesh;
    bool isQuad = false;
    // Sphere and disk
    Vec3 center{0, 0, 0};
    float radius = 1.0f;
    Vec3 normal{0, 1, 0}; // disk only: the front side
    // The shape's own axes in the space of its group (unit; pbrt-v4's object space, whose z is
    // a sphere's pole and a disk's normal): where (u, v) are measured, phi from frameX towards
    // frameY about frameZ (accel/embree_scene.cpp, sphereUv and diskUv).
    Vec3 frameX{1, 0, 0}, frameY{0, 1, 0}, frameZ{0, 0, 1};
    // Cut-out (pbrt-v4's shape "alpha"): a hit where alpha(uv) is 0 is ignored; between 0 and 1
    // it is kept with that probability (a hash of the ray), as pbrt-v4 does.
    FloatParam alpha{1.0f};
    // A homogeneous absorbing medium filling the closed shape (pbrt-v4's MediumInterface
    // "inside"): radiance travelling a distance d inside is attenuated by exp(-sigmaA d).
    Vec3 interiorAbsorption{0.0f, 0.0f, 0.0f};

    bool isEmissive() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
    Bounds3 bounds() const;
};

struct Node;

// A node of the hierarchy. Groups own children; an instance refers to a prototype group held in
// Scene::prototypes. `transform` maps the node's space into its parent's.
struct Node {
    enum class Kind { Group, Instance, Shape };
    Kind kind = Kind::Group;
    std::string name;
    Affine transform;
    std::vector<std::unique_ptr<Node>> children; // Group
    const Node* prototype = nullptr;             // Instance
    Shape shape;                                 // Shape
    Bounds3 bounds;                              // in the parent's space (computeBounds)
};

enum class LightType { Point, Spot, Directional, Environment, Goniometric };

struct Image;

// How an environment image covers the sphere of directions (in the light's own space, where +z
// is "up" for lat-long maps as in pbrt-v3 / Mitsuba, and pbrt-v4's equal-area octahedral
// mapping (Clarberg 2008) covers a square image).
enum class EnvironmentMapping { EqualArea, LatLong };

// Lights without geometry. Emissive shapes are area lights; they live in the tree.
struct Light {
    LightType type = LightType::Point;
    std::string name;
    Vec3 position{0, 0, 0};     // point, spot
    Vec3 direction{0, -1, 0};   // spot: where it points; directional: where light travels
    Vec3 intensity{1, 1, 1};    // point, spot: W/sr; directional: irradiance; environment: radiance
    // The intensity's own spectrum, as Shape::emissionSpectrum (an environment's only without
    // an image).
    EmissionSpectrumRef spectrum;
    float coneAngle = 30.0f;    // spot: full-intensity half angle, degrees
    float falloffAngle = 5.0f;  // spot: smooth falloff beyond the cone, degrees
    // Environment and goniometric lights: an image (linear RGB) multiplying `intensity`, and
    // the light's own frame (light space -> world; rotation only). Environment: radiance from
    // direction w is intensity * image(lookup(toWorld^-1 w)). Goniometric: intensity * image
    // in the equal-area parameterisation of the emitted direction (pbrt-v4).
    std::shared_ptr<const Image> image;
    std::string imageFile; // the file `image` was read from (outputs must not replace it)
    EnvironmentMapping mapping = EnvironmentMapping::EqualArea;
    Affine toWorld;
};

// Pixel reconstruction filter. The camera emitter importance-samples it: each sample's film
// position is drawn from |f| and carries the weight f / pdf (1 for positive filters), so the
// film stays a weighted average per pixel (pbrt-v4's FilterSampler approach).
struct PixelFilter {
    enum class Type { Box, Triangle, Gaussian, Mitchell, Lanczos };
    Type type = Type::Box;
    Vec2 radius{0.5f, 0.5f};
    float sigma = 0.5f;            // gaussian
    float b = 1.0f / 3.0f, c = 1.0f / 3.0f; // mitchell
    float tau = 3.0f;              // lanczos (sinc)
};

struct Camera {
    Vec3 position{0, 0, 5};
    Vec3 lookAt{0, 0, 0};
    Vec3 up{0, 1, 0};
    float fovY = 40.0f; // vertical field of view, degrees
    int width = 512, height = 512;
    float apertureRadius = 0.0f; // thin lens; 0 = pinhole
    float focusDistance = 0.0f;  // 0 = distance to lookAt
    PixelFilter filter;          // JSON default: box of radius 0.5; pbrt default: gaussian 1.5
};

// The film's sensor as pbrt-v4's "rgb" film with its default "cie1931" sensor defines it
// (engine/film_sensor.h): the image is scaled by the imaging ratio exposureTime * iso / 100 and,
// with whiteBalance > 0 (kelvin), white balanced from the daylight of that temperature to the
// colour space's white. The defaults change nothing.
struct FilmSensor {
    double iso = 100;
    double exposureTime = 1; // the camera's shutterclose - shutteropen
    double whiteBalance = 0; // 0: none
    bool passthrough() const { return iso == 100 && exposureTime == 1 && whiteBalance == 0; }
};

// Render settings that a scene file may carry; the CLI overrides each one it sets.
struct SceneRenderSettings {
    std::string mode;  // empty: the CLI default
    int spp = 0;       // 0: the mode's default
    int maxDepth = 0;  // 0: the mode's default
    int lightSamples = 0;
    long long seed = -1; // -1: default
    bool spectral = false; // render spectrally (docs/spectral.md)
    // A pbrt-v4 file's Integrator "sppm" (docs/pbrt-import.md): gi's caustic photons per pass,
    // its caustic radius (the first pass's radius at most) and its photons' depth; 0: gi's own.
    int photonsPerPass = 0;
    float photonRadius = 0.0f;
    int maxPhotonDepth = 0;
};

struct Scene {
    std::string path; // file it came from, for messages
    Camera camera;
    FilmSensor sensor;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Light> lights;
    std::unique_ptr<Node> root;                        // a group
    std::vector<std::unique_ptr<Node>> prototypes;     // groups placed by instances
    SceneRenderSettings render;

    int findMaterial(const std::string& name) const; // -1 if absent
    // Every image file the scene was read with (image textures, environment and goniometric
    // light images), as the loader resolved them: an output must not replace one of them.
    std::vector<std::string> imageFiles() const;
    void computeBounds(); // fills Node::bounds bottom-up
    Bounds3 worldBounds() const;
};

} // namespace rayproc
