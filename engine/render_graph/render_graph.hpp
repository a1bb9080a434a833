#pragma once
// Render graph in the spirit of Filament's FrameGraph and Granite's RenderGraph. A pass declares
// in its setup callback (run at once, no Vulkan calls) which resources it reads and writes and
// how; its execute callback (run later) records commands. compile() is pure CPU work that
// validates the declarations, orders passes by their dependencies, culls passes whose results
// nothing uses, computes resource lifetimes and the synchronization2 barriers before each pass.
// The returned CompiledGraph is plain data so tests can inspect the plan. Passes never place
// barriers themselves.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

namespace gt::vk {
class Context;
class Image;
class Buffer;
class TimestampPool;
} // namespace gt::vk

namespace gt::rg {

// Every declared use maps to one (stage, access, layout) triple: see accessInfo().
enum class Access : uint8_t {
    StorageRead,      // compute shader imageLoad / SSBO read
    StorageWrite,     // compute shader imageStore / SSBO write
    StorageReadWrite, // both in one pass
    SampledCompute,   // texture() in a compute shader
    UniformRead,      // uniform buffer or uniform texel buffer in a compute shader
    TransferSrc,
    TransferDst,
    HostRead, // the CPU reads it after the frame (readback buffers)
    Present,  // handed to the presentation engine
};

struct AccessInfo {
    VkPipelineStageFlags2 stage;
    VkAccessFlags2 access;
    VkImageLayout layout;
    bool writes;
    bool reads;
};
[[nodiscard]] AccessInfo accessInfo(Access access) noexcept;
[[nodiscard]] const char* toString(Access access) noexcept;

template <typename Tag> struct Handle {
    uint32_t index = ~0u;
    uint32_t version = 0;
    [[nodiscard]] bool valid() const noexcept { return index != ~0u; }
    friend bool operator==(const Handle&, const Handle&) = default;
};
using TextureId = Handle<struct TextureTag>;
using BufferId = Handle<struct BufferTag>;

enum class SizeMode : uint8_t { Absolute, OutputRelative };

struct TextureDesc {
    VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    SizeMode sizeMode = SizeMode::OutputRelative;
    float width = 1.0f;  // pixels (Absolute) or a factor of the output width
    float height = 1.0f; // pixels (Absolute) or a factor of the output height
};

struct BufferDesc {
    VkDeviceSize size = 0;
};

// A resource the graph does not own: the caller keeps it alive until the frame is finished.
struct ImportedTexture {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0, height = 0;
    std::optional<Access> initialAccess; // how it was last used; empty = contents undefined
    std::optional<Access> finalAccess;   // transition to this after the frame, if set
};

struct ImportedBuffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
    std::optional<Access> initialAccess; // empty = written by the host before submission
    std::optional<Access> finalAccess;
};

struct Barrier {
    uint32_t resource = 0;
    bool image = false;
    VkPipelineStageFlags2 srcStage = VK_PIPELINE_STAGE_2_NONE;
    VkAccessFlags2 srcAccess = VK_ACCESS_2_NONE;
    VkPipelineStageFlags2 dstStage = VK_PIPELINE_STAGE_2_NONE;
    VkAccessFlags2 dstAccess = VK_ACCESS_2_NONE;
    VkImageLayout oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImageLayout newLayout = VK_IMAGE_LAYOUT_UNDEFINED;
};

struct Lifetime {
    int firstPass = -1; // position in CompiledGraph::order, -1 when unused
    int lastPass = -1;
};

struct CompiledPass {
    uint32_t pass = 0;             // index in declaration order
    std::vector<Barrier> barriers; // placed before the pass
};

struct CompiledGraph {
    std::vector<CompiledPass> passes; // in execution order
    std::vector<uint32_t> culled;     // declaration indices of culled passes
    std::vector<Lifetime> lifetimes;  // per resource
    std::vector<Barrier> finalBarriers;
    std::vector<VkImageUsageFlags> imageUsage;   // per resource (transients get these bits)
    std::vector<VkBufferUsageFlags> bufferUsage; // per resource
    [[nodiscard]] std::vector<uint32_t> order() const;
};

class RenderGraph;

class PassBuilder {
public:
    [[nodiscard]] TextureId createTexture(std::string_view name, const TextureDesc& desc);
    [[nodiscard]] BufferId createBuffer(std::string_view name, const BufferDesc& desc);
    // `expected` checks the format (VK_FORMAT_UNDEFINED: any).
    [[nodiscard]] TextureId read(TextureId t, Access a, VkFormat expected = VK_FORMAT_UNDEFINED);
    [[nodiscard]] BufferId read(BufferId b, Access a);
    // Returns the next version; the handle passed in becomes stale for writing.
    [[nodiscard]] TextureId write(TextureId t, Access a, VkFormat expected = VK_FORMAT_UNDEFINED);
    [[nodiscard]] BufferId write(BufferId b, Access a);
    void dependsOn(std::string_view passName); // explicit order: run after that pass
    void sideEffect();                         // never culled

private:
    friend class RenderGraph;
    PassBuilder(RenderGraph& graph, uint32_t pass) : mGraph(graph), mPass(pass) {}
    RenderGraph& mGraph;
    uint32_t mPass;
};

struct ResolvedTexture {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0, height = 0;
};

class PassResources {
public:
    [[nodiscard]] const ResolvedTexture& texture(TextureId t) const;
    [[nodiscard]] VkBuffer buffer(BufferId b) const;
    [[nodiscard]] VkDeviceSize bufferSize(BufferId b) const;

private:
    friend class RenderGraph;
    std::vector<ResolvedTexture> mTextures;
    std::vector<std::pair<VkBuffer, VkDeviceSize>> mBuffers;
};

struct PassTiming {
    std::string name;
    double gpuMs = 0.0;
};

struct FrameTimings {
    std::vector<PassTiming> passes;
    double gpuMs = 0.0; // first pass start to last pass end
};

// Transient images and buffers that survive between frames of the same shape.
class TransientPool {
public:
    explicit TransientPool(vk::Context& ctx);
    ~TransientPool();
    TransientPool(const TransientPool&) = delete;
    TransientPool& operator=(const TransientPool&) = delete;
    vk::Image& image(const std::string& name, uint32_t w, uint32_t h, VkFormat f,
                     VkImageUsageFlags usage);
    vk::Buffer& buffer(const std::string& name, VkDeviceSize size, VkBufferUsageFlags usage);
    [[nodiscard]] vk::Context& context() noexcept { return mCtx; }

private:
    struct Impl;
    vk::Context& mCtx;
    std::unique_ptr<Impl> mImpl;
};

class RenderGraph {
public:
    RenderGraph(uint32_t outputWidth, uint32_t outputHeight);
    ~RenderGraph();
    RenderGraph(const RenderGraph&) = delete;
    RenderGraph& operator=(const RenderGraph&) = delete;

    using Execute = std::function<void(const PassResources&, VkCommandBuffer)>;

    template <typename Data, typename Setup, typename Exec>
    requires std::invocable<Setup&, PassBuilder&, Data&> &&
        std::invocable<Exec&, const PassResources&, const Data&, VkCommandBuffer>
    const Data& addPass(std::string_view name, Setup&& setup, Exec&& execute) {
        auto data = std::make_shared<Data>();
        const uint32_t index = beginPass(name);
        PassBuilder builder(*this, index);
        setup(builder, *data);
        setExecute(index,
                   [data, exec = std::forward<Exec>(execute)](
                       const PassResources& r, VkCommandBuffer cmd) { exec(r, *data, cmd); });
        return *data;
    }

    [[nodiscard]] TextureId importTexture(std::string_view name, const ImportedTexture& texture);
    [[nodiscard]] BufferId importBuffer(std::string_view name, const ImportedBuffer& buffer);

    [[nodiscard]] CompiledGraph compile() const; // throws GraphError
    // Records, submits and waits; returns the per-pass GPU times (timestamps).
    FrameTimings execute(const CompiledGraph& compiled, TransientPool& pool);
    [[nodiscard]] std::string toDot(const CompiledGraph& compiled) const;

    [[nodiscard]] std::size_t passCount() const noexcept;
    [[nodiscard]] const std::string& passName(uint32_t pass) const;
    [[nodiscard]] const std::string& resourceName(uint32_t resource) const;
    [[nodiscard]] uint32_t outputWidth() const noexcept { return mWidth; }
    [[nodiscard]] uint32_t outputHeight() const noexcept { return mHeight; }

private:
    friend class PassBuilder;
    struct Resource;
    struct Use;
    struct Pass;
    uint32_t beginPass(std::string_view name);
    void setExecute(uint32_t pass, Execute execute);
    uint32_t addResource(Resource resource);
    void addUse(uint32_t pass, Use use);
    [[nodiscard]] std::pair<uint32_t, uint32_t> textureExtent(const Resource& r) const;

    uint32_t mWidth, mHeight;
    std::vector<Pass> mPasses;
    std::vector<Resource> mResources;
};

} // namespace gt::rg
