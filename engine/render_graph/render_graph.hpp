#pragma once
// Render graph in the spirit of Filament's FrameGraph and Granite's RenderGraph. A pass declares
// in its setup callback (run at once, no Vulkan calls) which resources it reads and writes and
// how; its execute callback (run later) records commands. compile() is pure CPU work that
// validates the declarations, orders passes by their dependencies, culls passes whose results
// nothing uses, computes resource lifetimes and the synchronization2 barriers before each pass.
// The returned CompiledGraph is plain data so tests can inspect the plan. Passes never place
// barriers themselves.
//
// record() writes the frame into a command buffer the caller owns and submits (a window or an
// OpenXR runtime decides when and with which semaphores); the GPU times are read from the
// frame's timestamp pool once the caller knows the frame finished (RecordedFrame::timings).
// Names given inside a scope (RenderGraph::scope) carry its prefix, so one pass can appear once
// per view ("left.taa", "right.taa"). History (a texture a pass reads next frame, such as TAA's)
// lives in a HistoryPool that outlives the graph: importHistory() hands out last frame's image
// and the one to write, and HistoryPool::commit() swaps them only after the frame was submitted.
#include <cstdint>
#include <functional>
#include <map>
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

namespace detail { // graph_declarations.hpp
struct Resource;
struct Use;
struct Pass;
struct Sink;
} // namespace detail

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
    // Drawn into inside a render pass (the overlay: a third-party backend records its draws
    // there; the graph places the barriers around the pass, never inside it).
    ColorAttachment,
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
    // A pass that declares Access::UniformRead may read it as a uniform texel buffer of this
    // format (PassResources::texelView): random reads of texels were far cheaper than of a
    // storage buffer's vec4s on lavapipe (docs/lavapipe.md). Undefined: no view.
    VkFormat texelFormat = VK_FORMAT_UNDEFINED;
};

// A resource the graph does not own: the caller keeps it alive until the frame is finished.
struct ImportedTexture {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE; // a view of exactly `layer` (and one mip level)
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0, height = 0;
    std::optional<Access> initialAccess; // how it was last used; empty = contents undefined
    std::optional<Access> finalAccess;   // transition to this after the frame, if set
    uint32_t layer = 0; // array layer the graph uses and transitions (an OpenXR array swapchain)
    // With no initialAccess: the stages a semaphore wait of this frame's submit covers (a
    // swapchain image's acquire). The first barrier chains to them, so its layout transition
    // waits for the image to be free.
    VkPipelineStageFlags2 acquireStage = VK_PIPELINE_STAGE_2_NONE;
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
    uint32_t layer = 0; // the image's array layer
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
    uint32_t layer = 0;
};

class PassResources {
public:
    [[nodiscard]] const ResolvedTexture& texture(TextureId t) const;
    [[nodiscard]] VkBuffer buffer(BufferId b) const;
    [[nodiscard]] VkDeviceSize bufferSize(BufferId b) const;
    // The texel view of a transient buffer created with BufferDesc::texelFormat and read this
    // frame as Access::UniformRead; throws GraphError for any other.
    [[nodiscard]] VkBufferView texelView(BufferId b) const;

private:
    friend class RenderGraph;
    std::vector<ResolvedTexture> mTextures;
    std::vector<std::pair<VkBuffer, VkDeviceSize>> mBuffers;
    std::vector<VkBufferView> mTexelViews;
};

struct PassTiming {
    std::string name;
    double gpuMs = 0.0;
};

struct FrameTimings {
    std::vector<PassTiming> passes;
    double gpuMs = 0.0; // first pass start to last pass end
};

// A frame as recorded: which passes wrote which timestamp pair, read once the frame finished.
class RecordedFrame {
public:
    RecordedFrame() = default;
    // Empty passes when the timestamps are not (yet) available.
    [[nodiscard]] FrameTimings timings() const;
    [[nodiscard]] const std::vector<std::string>& passNames() const noexcept { return mNames; }

private:
    friend class RenderGraph;
    const vk::TimestampPool* mTimestamps = nullptr;
    std::vector<std::string> mNames; // in execution order, query pair i = passes i
};

// Transient images and buffers that survive between frames of the same shape. Use one pool per
// frame in flight: an image replaced here (a new size) is destroyed at once, which is safe only
// when no frame still in flight uses this pool.
class TransientPool {
public:
    explicit TransientPool(vk::Context& ctx);
    ~TransientPool();
    TransientPool(const TransientPool&) = delete;
    TransientPool& operator=(const TransientPool&) = delete;
    vk::Image& image(const std::string& name, uint32_t w, uint32_t h, VkFormat f,
                     VkImageUsageFlags usage);
    // A buffer made again where its size changed or it lacks one of `usage`'s bits.
    vk::Buffer& buffer(const std::string& name, VkDeviceSize size, VkBufferUsageFlags usage);
    // A view of the buffer `name` (made by buffer() before), kept while the buffer is.
    VkBufferView texelView(const std::string& name, VkFormat format);
    [[nodiscard]] vk::Context& context() noexcept { return mCtx; }
    [[nodiscard]] std::size_t imageCount() const noexcept;
    // Images and buffers created so far (a reused transient is not created again).
    [[nodiscard]] std::size_t created() const noexcept;
    // Device memory of the images it holds now (of `extent` only, where given).
    [[nodiscard]] VkDeviceSize imageBytes(std::optional<VkExtent2D> extent = {}) const noexcept;

private:
    struct Impl;
    vk::Context& mCtx;
    std::unique_ptr<Impl> mImpl;
};

// Holds what a value retires (an image resized away) until every frame that might still read it
// has finished: `frame` is the number of the frame being recorded when it was retired.
class DeferredRelease {
public:
    void retire(std::shared_ptr<void> object, uint64_t frame);
    // Every frame up to and including `frame` has finished.
    void collect(uint64_t frame);
    void clear() noexcept { mObjects.clear(); }
    [[nodiscard]] std::size_t pending() const noexcept { return mObjects.size(); }

private:
    std::vector<std::pair<uint64_t, std::shared_ptr<void>>> mObjects;
};

// Textures a pass reads in the next frame (TAA's history), owned across frames. Each name holds
// two images: the one last committed (read) and the one being written. A frame that fails before
// its submit never commits, so the next frame reads the same history as it would have.
class HistoryPool {
public:
    // `release` (may be null) keeps images replaced by a resize alive for frames in flight.
    HistoryPool(vk::Context& ctx, DeferredRelease* release = nullptr);
    ~HistoryPool();
    HistoryPool(const HistoryPool&) = delete;
    HistoryPool& operator=(const HistoryPool&) = delete;
    // Makes the next frame start without history for `name` (a saccade, a camera cut).
    void invalidate(std::string_view name);
    // Every history whose name starts with `prefix` (a view's, "left.").
    void invalidatePrefix(std::string_view prefix);
    void invalidateAll();
    // Swaps read and write images of every history `graph` imported. Call after its submit.
    void commit(const RenderGraph& graph);
    // Frames accumulated since the history of `name` was last reset (0: none yet).
    [[nodiscard]] uint32_t frames(std::string_view name) const;
    // Whether `name` holds a committed frame of this size and format (what readHistory would
    // hand out as valid): a resize replaces the images, so a pass that skips frames asks first.
    [[nodiscard]] bool holds(std::string_view name, uint32_t width, uint32_t height,
                             VkFormat format) const;
    void setFrameNumber(uint64_t frame) noexcept { mFrame = frame; }
    // Device memory of every history's two images (of `extent` only, where given).
    [[nodiscard]] VkDeviceSize imageBytes(std::optional<VkExtent2D> extent = {}) const noexcept;

private:
    friend class RenderGraph;
    struct Entry;
    Entry& entry(const std::string& name, uint32_t w, uint32_t h, VkFormat f);
    vk::Context& mCtx;
    DeferredRelease* mRelease;
    uint64_t mFrame = 0;
    std::map<std::string, std::unique_ptr<Entry>, std::less<>> mEntries;
};

// Last frame's texture of a history (valid: it holds a committed frame of the same size) and the
// texture this frame writes, which becomes the next frame's `previous` once committed.
struct HistoryTextures {
    TextureId previous;
    TextureId next;
    bool valid = false;
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
    // `format`, `width` and `height` describe the history image (absolute size).
    [[nodiscard]] HistoryTextures importHistory(HistoryPool& pool, std::string_view name,
                                                VkFormat format, uint32_t width, uint32_t height);
    // Last frame's image only (`next` stays invalid): a pass that skips this frame (a layer
    // updated at half rate) still reads what it wrote before, and commit() leaves it as it is.
    [[nodiscard]] HistoryTextures readHistory(HistoryPool& pool, std::string_view name,
                                              VkFormat format, uint32_t width, uint32_t height);

    // The version of `t` (or `b`) is a result of the frame: its producers are never culled and
    // it is left in `finalAccess` (Present for a swapchain image, StorageRead for a texture a
    // later frame reads, HostRead for a readback) — a sink, not an empty pass.
    void sink(TextureId t, Access finalAccess);
    void sink(BufferId b, Access finalAccess);

    // Every pass and resource named while the returned guard lives gets `prefix` + "." in front
    // ("left" -> "left.taa"); scopes nest. dependsOn() names resolve in the current scope.
    class Scope {
    public:
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;
        ~Scope();

    private:
        friend class RenderGraph;
        Scope(RenderGraph& graph, std::size_t restore, uint32_t w, uint32_t h)
            : mGraph(graph), mRestore(restore), mWidth(w), mHeight(h) {}
        RenderGraph& mGraph;
        std::size_t mRestore;
        uint32_t mWidth, mHeight; // the enclosing scope's size, restored on exit
    };
    // With a size, OutputRelative textures created inside the scope and outputWidth() /
    // outputHeight() refer to it (a view smaller than the graph's output, e.g. one eye).
    [[nodiscard]] Scope scope(std::string_view prefix, uint32_t width = 0, uint32_t height = 0);
    [[nodiscard]] std::string scopedName(std::string_view name) const;

    [[nodiscard]] CompiledGraph compile() const; // throws GraphError
    // Records the frame into `cmd` (begun by the caller, who also submits it): per pass its
    // barriers, a timestamp pair and its commands; then the final transitions. The timestamp
    // pool must hold 2 queries per compiled pass (see timestampCount) and is reset here.
    [[nodiscard]] RecordedFrame record(const CompiledGraph& compiled, TransientPool& pool,
                                       vk::TimestampPool& timestamps, VkCommandBuffer cmd);
    [[nodiscard]] static uint32_t timestampCount(const CompiledGraph& compiled) noexcept;
    // Tests and one-off work: record into a fresh command buffer, submit, wait, read the times.
    FrameTimings executeAndWait(const CompiledGraph& compiled, TransientPool& pool);
    [[nodiscard]] std::string toDot(const CompiledGraph& compiled) const;

    [[nodiscard]] std::size_t passCount() const noexcept;
    [[nodiscard]] const std::string& passName(uint32_t pass) const;
    [[nodiscard]] const std::string& resourceName(uint32_t resource) const;
    // The current scope's size (the graph's output size outside any sized scope).
    [[nodiscard]] uint32_t outputWidth() const noexcept { return mScopeWidth; }
    [[nodiscard]] uint32_t outputHeight() const noexcept { return mScopeHeight; }

private:
    friend class PassBuilder;
    friend class HistoryPool;
    // One of a history's two images, imported (importHistory, readHistory).
    TextureId importHistoryImage(const HistoryPool::Entry& e, int index, std::string_view name,
                                 VkFormat format, uint32_t width, uint32_t height);
    using Resource = detail::Resource;
    using Use = detail::Use;
    using Pass = detail::Pass;
    using Sink = detail::Sink;
    uint32_t beginPass(std::string_view name);
    void setExecute(uint32_t pass, Execute execute);
    uint32_t addResource(Resource resource);
    void addUse(uint32_t pass, Use use);
    [[nodiscard]] std::pair<uint32_t, uint32_t> textureExtent(const Resource& r) const;

    uint32_t mWidth, mHeight;
    uint32_t mScopeWidth, mScopeHeight;
    std::vector<Pass> mPasses;
    std::vector<Resource> mResources;
    std::string mScope; // current prefix, "" or ending in '.'
    std::vector<Sink> mSinks;
    struct HistoryUse {
        HistoryPool* pool;
        std::string name;
        int writeIndex;
    };
    std::vector<HistoryUse> mHistories;
};

} // namespace gt::rg
