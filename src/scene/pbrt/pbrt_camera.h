// pbrt's camera and film as rayproc's Camera.
//
// pbrt's camera space is left-handed: x is the image's right, y its up, z the view direction.
// rayproc's camera is right-handed: its right is cross(forward, up). So the camera transform
// decides whether a pbrt image is rayproc's image or its mirror: the common `Scale -1 1 1`
// before `LookAt` (Bitterli's and other exported scenes) makes pbrt's x axis cross(forward, up)
// and rayproc reproduces it directly; a plain `LookAt` makes it -cross(forward, up), and pbrt
// shows the mirror image of what a right-handed camera would. rayproc has no mirror flag, so the
// importer then mirrors the whole world about the camera's vertical plane (the plane through the
// eye spanned by the view and up directions): seen through rayproc's camera, the mirrored world
// is exactly pbrt's image.
//
// The field of view: pbrt's "fov" spans the shorter image axis (the screen window is [-1, 1]
// on that axis and [-aspect, aspect] on the other); rayproc's fovY is vertical.
#pragma once

#include "scene/pbrt/pbrt_params.h"
#include "scene/pbrt/pbrt_transform.h"
#include "scene/pbrt/pbrt_warnings.h"
#include "scene/scene.h"

namespace rayproc::pbrt {

struct CameraDirective {
    bool given = false;
    Mat4 cameraFromWorld; // the CTM at the Camera directive
    std::string type = "perspective";
    ParamList params;
    SourceLoc loc;
};

struct FilmDirective {
    bool given = false;
    ParamList params;
    SourceLoc loc;
};

struct FilterDirective {
    bool given = false;
    std::string type;
    ParamList params;
    SourceLoc loc;
};

// pbrt-v4's pixel filter as Camera::filter: without a PixelFilter directive pbrt-v4's default,
// a gaussian of radius 1.5 and sigma 0.5. Radii must be positive (an input error otherwise);
// an unknown type warns and takes the default. Mitchell's and lanczos's negative lobes are
// clamped by the camera emitter, which warns here.
PixelFilter convertFilter(const FilterDirective& filter, Warnings& warnings);

// Fills scene.camera and returns the transform every world-space shape and light must take:
// identity, or the mirror described above. `worldBegin` locates messages about a default camera.
Mat4 convertCamera(const CameraDirective& camera, const FilmDirective& film, Scene& scene,
                   Warnings& warnings, const SourceLoc& worldBegin);

} // namespace rayproc::pbrt
