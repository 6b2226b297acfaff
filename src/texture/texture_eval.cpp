#include "texture/texture_eval.h"

namespace rayproc {

Vec3 evalTexture(const Scene& scene, int index, const TextureContext& ctx) {
    const Texture& t = scene.textures[std::size_t(index)];
    switch (t.type) {
    case TextureType::Constant: return t.value;
    default: return t.value;
    }
}

float evalFloatTexture(const Scene& scene, int index, const TextureContext& ctx) {
    return evalTexture(scene, index, ctx).x;
}

} // namespace rayproc
