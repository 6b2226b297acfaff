// A scene material as the BSDF kernels see it (path mode and the photon pass).
#pragma once

#include "kernels/bsdf_sampling.h"
#include "scene/scene.h"

namespace rayproc {

inline kernels::BsdfParams bsdfOf(const Material& m) {
    kernels::BsdfParams b;
    b.color = m.color;
    b.ior = m.ior;
    b.alpha = kernels::ggxAlpha(m.roughness);
    switch (m.type) {
    case MaterialType::Diffuse: b.kind = kernels::BsdfKind::Diffuse; break;
    case MaterialType::Mirror: b.kind = kernels::BsdfKind::Mirror; break;
    case MaterialType::Dielectric: b.kind = kernels::BsdfKind::Dielectric; break;
    case MaterialType::Glossy: b.kind = kernels::BsdfKind::Glossy; break;
    }
    return b;
}

} // namespace rayproc
