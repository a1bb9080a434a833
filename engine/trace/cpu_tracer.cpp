#include "trace/cpu_tracer.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

#include "trace/gpu_scene.hpp"

namespace gt::trace {

namespace {
constexpr float kPi = 3.14159265358979f;

float srgbToLinear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

glm::vec4 unpackTexel(uint32_t p) {
    return {srgbToLinear(static_cast<float>(p & 0xffu) / 255.0f),
            srgbToLinear(static_cast<float>((p >> 8) & 0xffu) / 255.0f),
            srgbToLinear(static_cast<float>((p >> 16) & 0xffu) / 255.0f),
            static_cast<float>(p >> 24) / 255.0f};
}

float offsetScale(glm::vec3 p) {
    return 1e-4f * std::max(1.0f, std::max(std::abs(p.x), std::max(std::abs(p.y), std::abs(p.z))));
}
} // namespace

uint32_t pcgHash(uint32_t v) noexcept {
    const uint32_t state = v * 747796405u + 2891336453u;
    const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

glm::vec2 sampleOffset(uint32_t pixelIndex, uint32_t sample, uint32_t count,
                       uint32_t frameSeed) noexcept {
    uint32_t sx = 1;
    while (sx * sx < count)
        ++sx;
    const uint32_t sy = (count + sx - 1) / sx;
    uint32_t h = pcgHash(pixelIndex ^ pcgHash(sample + frameSeed * 0x9E3779B9u));
    const float r1 = static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
    h = pcgHash(h);
    const float r2 = static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
    return {(static_cast<float>(sample % sx) + r1) / static_cast<float>(sx),
            (static_cast<float>(sample / sx) + r2) / static_cast<float>(sy)};
}

CpuTracer::CpuTracer(const scene::Scene& scene, const scene::Bvh& bvh) : mScene(scene), mBvh(bvh) {
    if (!scene.hasAlphaMask()) {
        return;
    }
    // alphaMode MASK (glTF 2.0, 3.9.4), as alphaRejects in trace.glsl.
    mAlphaTest = [this](uint32_t i, float u, float v) {
        const uint32_t tri = mBvh.triangleOrder()[i];
        const uint32_t material = mScene.triangleMaterial[tri];
        const float cutoff = mScene.materials[material].alphaCutoff;
        if (cutoff < 0.0f) {
            return true;
        }
        const scene::Vertex* x = &mScene.vertices[3 * static_cast<std::size_t>(tri)];
        const glm::vec2 uv = (1.0f - u - v) * x[0].uv + u * x[1].uv + v * x[2].uv;
        return baseColor(material, uv).a >= cutoff;
    };
}

glm::vec3 CpuTracer::sky(glm::vec3 d) const {
    if (mScene.environment.width > 0) return scene::sampleEnvironment(mScene.environment, d);
    if (d.y >= 0.0f) return glm::mix(mScene.sky.horizon, mScene.sky.zenith, d.y);
    return glm::mix(mScene.sky.horizon, mScene.sky.ground, std::min(1.0f, -4.0f * d.y));
}

glm::vec4 CpuTracer::baseColor(uint32_t material, glm::vec2 uv) const {
    const scene::Material& m = mScene.materials[material];
    if (m.baseColorTexture < 0) return m.baseColor;
    const scene::Texture& t = mScene.textures[static_cast<std::size_t>(m.baseColorTexture)];
    // Bilinear with repeat wrapping, texel centres at half-integers.
    const float x = uv.x * static_cast<float>(t.width) - 0.5f;
    const float y = uv.y * static_cast<float>(t.height) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;
    auto wrap = [](int i, int n) { return ((i % n) + n) % n; };
    const int w = static_cast<int>(t.width), h = static_cast<int>(t.height);
    const int x0 = wrap(static_cast<int>(fx), w), x1 = wrap(static_cast<int>(fx) + 1, w);
    const int y0 = wrap(static_cast<int>(fy), h), y1 = wrap(static_cast<int>(fy) + 1, h);
    auto at = [&](int xx, int yy) {
        return unpackTexel(t.rgba[static_cast<std::size_t>(yy * w + xx)]);
    };
    const glm::vec4 c =
        glm::mix(glm::mix(at(x0, y0), at(x1, y0), ax), glm::mix(at(x0, y1), at(x1, y1), ax), ay);
    return m.baseColor * c;
}

glm::vec3 CpuTracer::radiance(const scene::Ray& primary) const {
    glm::vec3 result(0.0f), throughput(1.0f);
    scene::Ray ray = primary;
    for (int bounce = 0; bounce < 2; ++bounce) {
        const scene::Hit hit = mBvh.intersect(ray, mAlphaTest);
        if (!hit.valid()) {
            result += throughput * sky(ray.direction);
            break;
        }
        const uint32_t tri = mBvh.triangleOrder()[hit.triangle];
        const scene::Vertex* v = &mScene.vertices[3 * tri];
        const float w0 = 1.0f - hit.u - hit.v;
        glm::vec3 n = glm::normalize(w0 * v[0].normal + hit.u * v[1].normal + hit.v * v[2].normal);
        const glm::vec2 uv = w0 * v[0].uv + hit.u * v[1].uv + hit.v * v[2].uv;
        const scene::BvhTriangle& bt = mBvh.triangles()[hit.triangle];
        glm::vec3 ng = glm::normalize(glm::cross(bt.e1, bt.e2));
        if (glm::dot(ng, ray.direction) > 0.0f) ng = -ng;
        if (glm::dot(n, ng) < 0.0f) n = -n;
        const uint32_t matIndex = mScene.triangleMaterial[tri];
        const scene::Material& m = mScene.materials[matIndex];
        const glm::vec3 base = glm::vec3(baseColor(matIndex, uv));
        if (m.unlit) { // KHR_materials_unlit, as the GPU tracer does
            result += throughput * base;
            break;
        }
        const glm::vec3 p = ray.origin + hit.t * ray.direction;
        const glm::vec3 origin = p + ng * offsetScale(p);

        glm::vec3 direct(0.0f);
        for (const scene::Light& l : mScene.lights) {
            glm::vec3 toLight;
            float dist;
            glm::vec3 e = l.color * l.intensity;
            if (l.type == scene::LightType::Directional) {
                toLight = -glm::normalize(l.direction);
                dist = std::numeric_limits<float>::infinity();
            } else {
                const glm::vec3 d = l.position - p;
                dist = glm::length(d);
                toLight = d / dist;
                float atten = 1.0f / std::max(dist * dist, 1e-4f);
                if (l.range > 0.0f) {
                    const float r = dist / l.range;
                    atten *= std::clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
                }
                if (l.type == scene::LightType::Spot) {
                    const float cd = glm::dot(glm::normalize(l.direction), -toLight);
                    const float s = std::clamp((cd - l.outerConeCos) /
                                                   std::max(l.innerConeCos - l.outerConeCos, 1e-4f),
                                               0.0f, 1.0f);
                    atten *= s * s;
                }
                e *= atten;
            }
            const float cosTheta = glm::dot(n, toLight);
            if (cosTheta <= 0.0f || glm::dot(e, e) == 0.0f) continue;
            scene::Ray shadow{origin, toLight, 0.0f,
                              std::isinf(dist) ? std::numeric_limits<float>::infinity()
                                               : dist * 0.999f};
            if (!mBvh.occluded(shadow, mAlphaTest)) direct += e * cosTheta;
        }
        const glm::vec3 albedo = base * (1.0f - m.metallic);
        const glm::vec3 ambient = mScene.sky.ambient * sky(n);
        result += throughput * (m.emissive + albedo * (direct / kPi + ambient));
        if (m.metallic <= 0.0f || bounce == 1) break;
        throughput *= m.metallic * base;
        ray = {origin, glm::reflect(ray.direction, n), 0.0f,
               std::numeric_limits<float>::infinity()};
    }
    return result;
}

std::vector<glm::vec4> CpuTracer::render(const TraceSettings& s) const {
    std::vector<glm::vec4> out(static_cast<std::size_t>(s.width) * s.height);
    const shaders::trace::CameraPush cam =
        s.frustum
            ? cameraPush(mScene.camera, *s.frustum)
            : cameraPush(mScene.camera, static_cast<float>(s.width) / static_cast<float>(s.height));
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) {
        pool.emplace_back([&, t] {
            for (uint32_t y = t; y < s.height; y += threads) {
                for (uint32_t x = 0; x < s.width; ++x) {
                    const uint32_t pixel = y * s.width + x;
                    glm::vec3 sum(0.0f);
                    for (uint32_t i = 0; i < s.raysPerPixel; ++i) {
                        const glm::vec2 o = sampleOffset(pixel, i, s.raysPerPixel, s.frameSeed);
                        const float sx =
                            (2.0f * (static_cast<float>(x) + o.x) / static_cast<float>(s.width) -
                             1.0f) *
                                cam.origin.w * cam.forward.w +
                            cam.right.w;
                        const float sy = (1.0f - 2.0f * (static_cast<float>(y) + o.y) /
                                                     static_cast<float>(s.height)) *
                                             cam.origin.w +
                                         cam.up.w;
                        const glm::vec3 dir =
                            glm::normalize(glm::vec3(cam.forward) + sx * glm::vec3(cam.right) +
                                           sy * glm::vec3(cam.up));
                        sum += radiance({glm::vec3(cam.origin), dir, 0.0f,
                                         std::numeric_limits<float>::infinity()});
                    }
                    out[pixel] = glm::vec4(sum / static_cast<float>(s.raysPerPixel), 1.0f);
                }
            }
        });
    }
    for (auto& th : pool)
        th.join();
    return out;
}

} // namespace gt::trace
