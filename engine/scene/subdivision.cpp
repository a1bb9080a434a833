#include "scene/subdivision.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include "core/error.hpp"

namespace gt::scene {

namespace {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

// The primvar OpenSubdiv interpolates: a point (Far's Clear/AddWithWeight protocol).
struct Point {
    glm::vec3 p{0.0f};
    void Clear(void* = nullptr) { p = glm::vec3(0.0f); }
    void AddWithWeight(const Point& src, float weight) { p += weight * src.p; }
};

std::unique_ptr<Far::TopologyRefiner> refiner(const SubdivisionCage& cage, uint32_t level) {
    std::size_t corners = 0;
    for (const uint32_t n : cage.faceSizes) {
        if (n < 3) {
            throw Error("cage '" + cage.name + "': a face with fewer than 3 corners");
        }
        corners += n;
    }
    if (corners != cage.indices.size()) {
        throw Error("cage '" + cage.name + "': face sizes do not match its indices");
    }
    for (const uint32_t i : cage.indices) {
        if (i >= cage.points.size()) {
            throw Error("cage '" + cage.name + "': index out of range");
        }
    }
    const std::vector<int> sizes(cage.faceSizes.begin(), cage.faceSizes.end());
    const std::vector<int> indices(cage.indices.begin(), cage.indices.end());
    Far::TopologyDescriptor desc;
    desc.numVertices = static_cast<int>(cage.points.size());
    desc.numFaces = static_cast<int>(sizes.size());
    desc.numVertsPerFace = sizes.data();
    desc.vertIndicesPerFace = indices.data();
    Sdc::Options options;
    options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> r(
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, options)));
    if (!r) {
        throw Error("cage '" + cage.name + "': OpenSubdiv rejected its topology");
    }
    Far::TopologyRefiner::UniformOptions uniform(static_cast<int>(level));
    uniform.fullTopologyInLastLevel = true; // the limit evaluation needs it
    r->RefineUniform(uniform);
    return r;
}

} // namespace

std::size_t refinedFaceCount(const SubdivisionCage& cage, uint32_t level) {
    return static_cast<std::size_t>(
        refiner(cage, level)->GetLevel(static_cast<int>(level)).GetNumFaces());
}

std::vector<Vertex> refineCage(const SubdivisionCage& cage, uint32_t level) {
    const std::unique_ptr<Far::TopologyRefiner> r = refiner(cage, level);
    std::vector<Point> points(static_cast<std::size_t>(r->GetNumVerticesTotal()));
    for (std::size_t i = 0; i < cage.points.size(); ++i) {
        points[i].p = cage.points[i];
    }
    const Far::PrimvarRefiner primvar(*r);
    Point* src = points.data();
    for (int l = 1; l <= static_cast<int>(level); ++l) {
        Point* dst = src + r->GetLevel(l - 1).GetNumVertices();
        primvar.Interpolate(l, src, dst);
        src = dst;
    }
    const Far::TopologyLevel& fine = r->GetLevel(static_cast<int>(level));
    const auto n = static_cast<std::size_t>(fine.GetNumVertices());
    std::vector<Point> limit(n), du(n), dv(n);
    primvar.Limit(src, limit, du, dv);
    std::vector<Vertex> out;
    for (int f = 0; f < fine.GetNumFaces(); ++f) {
        const Far::ConstIndexArray v = fine.GetFaceVertices(f);
        // A fan per face (quads after the first refinement; the cage's own polygons at level 0).
        for (int k = 1; k + 1 < v.size(); ++k) {
            const int tri[3] = {v[0], v[k], v[k + 1]};
            const glm::vec3 face = glm::cross(limit[static_cast<std::size_t>(tri[1])].p -
                                                  limit[static_cast<std::size_t>(tri[0])].p,
                                              limit[static_cast<std::size_t>(tri[2])].p -
                                                  limit[static_cast<std::size_t>(tri[0])].p);
            for (const int i : tri) {
                const auto u = static_cast<std::size_t>(i);
                glm::vec3 normal = glm::cross(du[u].p, dv[u].p);
                const float len = glm::length(normal);
                // A degenerate tangent frame (an extraordinary point's limit): the face's normal.
                normal = len > 1e-12f ? normal / len : glm::normalize(face);
                if (glm::dot(normal, face) < 0.0f) {
                    normal = -normal; // the winding's side
                }
                out.push_back({limit[u].p, normal, glm::vec2(0.0f)});
            }
        }
    }
    return out;
}

uint32_t lodForPitch(float pitch, uint32_t levels) {
    if (levels <= 1 || !(pitch >= 4.0f)) {
        return 0;
    }
    const auto l = static_cast<uint32_t>(std::floor(std::log2(pitch / 2.0f)));
    return std::min(l, levels - 1);
}

namespace {

void appendRefined(const std::vector<SubdivisionCage>& cages, std::size_t materials, uint32_t level,
                   Scene& out) {
    for (const SubdivisionCage& cage : cages) {
        if (cage.material >= materials) {
            throw Error("cage '" + cage.name + "': material out of range");
        }
        const std::vector<Vertex> tris = refineCage(cage, level);
        out.vertices.insert(out.vertices.end(), tris.begin(), tris.end());
        out.triangleMaterial.insert(out.triangleMaterial.end(), tris.size() / 3, cage.material);
    }
}

} // namespace

void refineCages(Scene& scene, uint32_t level) {
    const std::vector<SubdivisionCage> cages = std::move(scene.cages);
    scene.cages.clear();
    appendRefined(cages, scene.materials.size(), level, scene);
}

Scene refinedGeometry(const Scene& scene, uint32_t level) {
    Scene out;
    out.name = scene.name;
    out.vertices = scene.vertices;
    out.triangleMaterial = scene.triangleMaterial;
    appendRefined(scene.cages, scene.materials.size(), level, out);
    return out;
}

} // namespace gt::scene
