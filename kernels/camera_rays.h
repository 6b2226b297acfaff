// Primary ray generation: SoA film positions in, SoA rays out.
#pragma once

#include "core/math.h"
#include "kernels/sampling.h"

namespace rayproc::kernels {

// Everything the kernel needs from a camera, precomputed once per render.
struct CameraFrame {
    Vec3 origin;
    Vec3 right, up, forward; // world-space unit axes
    float tanHalfFovY = 0.5f;
    float aspect = 1.0f;      // width / height
    float width = 1, height = 1;
    float lensRadius = 0.0f;
    float focusDistance = 1.0f;
};

// Film positions (pixels, y down) and lens samples -> unit-direction rays.
inline void generateCameraRays(const CameraFrame& c, int n, const float* filmX, const float* filmY,
                               const float* lensU, const float* lensV, float* ox, float* oy,
                               float* oz, float* dx, float* dy, float* dz) {
    for (int i = 0; i < n; ++i) {
        float sx = (2.0f * filmX[i] / c.width - 1.0f) * c.tanHalfFovY * c.aspect;
        float sy = (1.0f - 2.0f * filmY[i] / c.height) * c.tanHalfFovY;
        Vec3 d = c.right * sx + c.up * sy + c.forward;
        Vec3 o = c.origin;
        if (c.lensRadius > 0) {
            // Thin lens: the point at focus distance along the pinhole ray stays sharp.
            Vec3 focus = o + d * c.focusDistance;
            Vec2 l = concentricDisk({lensU[i], lensV[i]});
            o = o + c.right * (l.x * c.lensRadius) + c.up * (l.y * c.lensRadius);
            d = focus - o;
        }
        d = normalize(d);
        ox[i] = o.x; oy[i] = o.y; oz[i] = o.z;
        dx[i] = d.x; dy[i] = d.y; dz[i] = d.z;
    }
}

} // namespace rayproc::kernels
