#pragma once
// What the passes' setup callbacks declare, as the render graph records it: resources, the
// versioned uses of each pass, explicit orders and sinks. Plain data, shared by the builder
// (render_graph.cpp) and the compile phases (compile_phases.hpp), and built by hand in tests.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "render_graph/render_graph.hpp"

namespace gt::rg::detail {

struct Resource {
    std::string name;
    bool image = false;
    bool imported = false;
    TextureDesc texture;
    BufferDesc buffer;
    ImportedTexture importedTexture;
    ImportedBuffer importedBuffer;
    uint32_t versions = 1;                  // highest version handed out + 1
    uint32_t baseWidth = 0, baseHeight = 0; // what OutputRelative sizes are relative to
};

struct Use {
    uint32_t resource = 0;
    uint32_t version = 0; // version read, or version written (the new one)
    Access access = Access::StorageRead;
    bool write = false;
    VkFormat expected = VK_FORMAT_UNDEFINED;
};

struct Pass {
    std::string name;
    std::vector<Use> uses;
    std::vector<std::string> after;
    bool sideEffect = false;
    std::function<void(const PassResources&, VkCommandBuffer)> execute;
};

// A version of a resource that is a result of the frame, left in `access` after it.
struct Sink {
    uint32_t resource, version;
    Access access;
};

// Everything compile() reads.
struct Declarations {
    std::span<const Pass> passes;
    std::span<const Resource> resources;
    std::span<const Sink> sinks;
};

} // namespace gt::rg::detail
