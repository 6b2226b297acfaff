#include "scene/scene.h"

namespace rayproc {

Bounds3 TriangleMesh::bounds() const {
    Bounds3 b;
    for (const Vec3& p : positions) b.extend(p);
    return b;
}

Bounds3 Shape::bounds() const {
    Bounds3 b;
    switch (type) {
    case ShapeType::Mesh:
        if (mesh) b = mesh->bounds();
        break;
    case ShapeType::Sphere:
    case ShapeType::Disk: // conservative: the disk's bounding sphere
        b.extend(center - Vec3(radius));
        b.extend(center + Vec3(radius));
        break;
    }
    return b;
}

int Scene::findMaterial(const std::string& name) const {
    for (std::size_t i = 0; i < materials.size(); ++i)
        if (materials[i].name == name) return int(i);
    return -1;
}

std::vector<std::string> Scene::imageFiles() const {
    std::vector<std::string> files;
    for (const Texture& t : textures)
        if (t.type == TextureType::Image && t.image) files.push_back(t.filename);
    for (const Light& l : lights)
        if (l.image && !l.imageFile.empty()) files.push_back(l.imageFile);
    return files;
}

namespace {
Bounds3 computeNodeBounds(Node& n) {
    Bounds3 local;
    switch (n.kind) {
    case Node::Kind::Shape: local = n.shape.bounds(); break;
    case Node::Kind::Group:
        for (auto& c : n.children) local.extend(computeNodeBounds(*c));
        break;
    case Node::Kind::Instance:
        if (n.prototype) local = n.prototype->transform.bounds(n.prototype->bounds);
        break;
    }
    n.bounds = n.kind == Node::Kind::Shape ? local : n.transform.bounds(local);
    return n.bounds;
}
} // namespace

void Scene::computeBounds() {
    // Prototypes first: instances read their bounds. A prototype's own transform applies
    // wherever it is placed, so its bounds stay in its local space plus that transform.
    for (auto& p : prototypes) {
        Bounds3 local;
        for (auto& c : p->children) local.extend(computeNodeBounds(*c));
        p->bounds = local;
    }
    if (root) computeNodeBounds(*root);
}

Bounds3 Scene::worldBounds() const { return root ? root->bounds : Bounds3{}; }

} // namespace rayproc
