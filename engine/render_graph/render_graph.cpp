#include "render_graph/render_graph.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <sstream>

#include "core/error.hpp"
#include "render_graph/compile_phases.hpp"
#include "render_graph/graph_declarations.hpp"
#include "vk/context.hpp"
#include "vk/query_pool.hpp"
#include "vk/resources.hpp"

namespace gt::rg {

namespace {

// Whether `image` is of `extent`, or any size where none is given (memory figures by size).
bool hasExtent(const vk::Image& image, std::optional<VkExtent2D> extent) noexcept {
    return !extent ||
           (image.desc().width == extent->width && image.desc().height == extent->height);
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Access vocabulary

AccessInfo accessInfo(Access a) noexcept {
    constexpr auto cs = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    switch (a) {
    case Access::StorageRead:
        return {cs, VK_ACCESS_2_SHADER_STORAGE_READ_BIT, VK_IMAGE_LAYOUT_GENERAL, false, true};
    case Access::StorageWrite:
        return {cs, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_IMAGE_LAYOUT_GENERAL, true, false};
    case Access::StorageReadWrite:
        return {cs, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                VK_IMAGE_LAYOUT_GENERAL, true, true};
    case Access::SampledCompute:
        return {cs, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                false, true};
    case Access::UniformRead:
        return {cs, VK_ACCESS_2_UNIFORM_READ_BIT | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, false, true};
    case Access::TransferSrc: // copies and blits
        return {VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_BLIT_BIT,
                VK_ACCESS_2_TRANSFER_READ_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, false, true};
    case Access::TransferDst: // copies, blits and clears
        return {VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_BLIT_BIT |
                    VK_PIPELINE_STAGE_2_CLEAR_BIT,
                VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, true, false};
    case Access::HostRead:
        return {VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT, VK_IMAGE_LAYOUT_GENERAL,
                false, true};
    case Access::Present:
        return {VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, false,
                true};
    case Access::ColorAttachment:
        return {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, true, true};
    }
    return {};
}

const char* toString(Access a) noexcept {
    switch (a) {
    case Access::StorageRead:
        return "storage-read";
    case Access::StorageWrite:
        return "storage-write";
    case Access::StorageReadWrite:
        return "storage-read-write";
    case Access::SampledCompute:
        return "sampled";
    case Access::UniformRead:
        return "uniform";
    case Access::TransferSrc:
        return "transfer-src";
    case Access::TransferDst:
        return "transfer-dst";
    case Access::HostRead:
        return "host-read";
    case Access::Present:
        return "present";
    case Access::ColorAttachment:
        return "color-attachment";
    }
    return "?";
}

// ---------------------------------------------------------------------------------------------
// Declarations

RenderGraph::RenderGraph(uint32_t outputWidth, uint32_t outputHeight)
    : mWidth(outputWidth), mHeight(outputHeight), mScopeWidth(outputWidth),
      mScopeHeight(outputHeight) {
    if (outputWidth == 0 || outputHeight == 0) throw GraphError("render graph output size is 0");
}
RenderGraph::~RenderGraph() = default;

std::size_t RenderGraph::passCount() const noexcept {
    return mPasses.size();
}
const std::string& RenderGraph::passName(uint32_t pass) const {
    return mPasses.at(pass).name;
}
const std::string& RenderGraph::resourceName(uint32_t r) const {
    return mResources.at(r).name;
}

std::string RenderGraph::scopedName(std::string_view name) const {
    return mScope + std::string(name);
}

RenderGraph::Scope RenderGraph::scope(std::string_view prefix, uint32_t width, uint32_t height) {
    if (prefix.empty()) throw GraphError("render graph scope with an empty name");
    if ((width == 0) != (height == 0)) throw GraphError("render graph scope with a 0 size");
    const std::size_t restore = mScope.size();
    const uint32_t w = mScopeWidth, h = mScopeHeight;
    mScope += std::string(prefix) + ".";
    if (width != 0) {
        mScopeWidth = width;
        mScopeHeight = height;
    }
    return Scope(*this, restore, w, h);
}

RenderGraph::Scope::~Scope() {
    mGraph.mScope.resize(mRestore);
    mGraph.mScopeWidth = mWidth;
    mGraph.mScopeHeight = mHeight;
}

uint32_t RenderGraph::beginPass(std::string_view unscoped) {
    const std::string name = scopedName(unscoped);
    for (const Pass& p : mPasses) {
        if (p.name == name) throw GraphError("two passes are named '" + name + "'");
    }
    mPasses.push_back(Pass{name, {}, {}, false, {}});
    return static_cast<uint32_t>(mPasses.size() - 1);
}

void RenderGraph::setExecute(uint32_t pass, Execute execute) {
    mPasses[pass].execute = std::move(execute);
}

uint32_t RenderGraph::addResource(Resource resource) {
    resource.name = mScope + resource.name;
    resource.baseWidth = mScopeWidth;
    resource.baseHeight = mScopeHeight;
    for (const Resource& r : mResources) {
        if (r.name == resource.name) {
            throw GraphError("two resources are named '" + resource.name + "'");
        }
    }
    mResources.push_back(std::move(resource));
    return static_cast<uint32_t>(mResources.size() - 1);
}

void RenderGraph::addUse(uint32_t pass, Use use) {
    mPasses[pass].uses.push_back(use);
}

TextureId RenderGraph::importTexture(std::string_view name, const ImportedTexture& texture) {
    Resource r;
    r.name = name;
    r.image = true;
    r.imported = true;
    r.importedTexture = texture;
    r.texture = {texture.format, SizeMode::Absolute, static_cast<float>(texture.width),
                 static_cast<float>(texture.height)};
    return {addResource(std::move(r)), 0};
}

BufferId RenderGraph::importBuffer(std::string_view name, const ImportedBuffer& buffer) {
    Resource r;
    r.name = name;
    r.imported = true;
    r.importedBuffer = buffer;
    r.buffer = {buffer.size};
    return {addResource(std::move(r)), 0};
}

void RenderGraph::sink(TextureId t, Access finalAccess) {
    if (!t.valid() || t.index >= mResources.size() || !mResources[t.index].image) {
        throw GraphError("sink of an invalid texture");
    }
    mSinks.push_back({t.index, t.version, finalAccess});
}

void RenderGraph::sink(BufferId b, Access finalAccess) {
    if (!b.valid() || b.index >= mResources.size() || mResources[b.index].image) {
        throw GraphError("sink of an invalid buffer");
    }
    mSinks.push_back({b.index, b.version, finalAccess});
}

TextureId PassBuilder::createTexture(std::string_view name, const TextureDesc& desc) {
    RenderGraph::Resource r;
    r.name = name;
    r.image = true;
    r.texture = desc;
    return {mGraph.addResource(std::move(r)), 0};
}

BufferId PassBuilder::createBuffer(std::string_view name, const BufferDesc& desc) {
    RenderGraph::Resource r;
    r.name = name;
    r.buffer = desc;
    return {mGraph.addResource(std::move(r)), 0};
}

TextureId PassBuilder::read(TextureId t, Access a, VkFormat expected) {
    if (!t.valid() || t.index >= mGraph.mResources.size() || !mGraph.mResources[t.index].image) {
        throw GraphError("pass '" + mGraph.mPasses[mPass].name + "' reads an invalid texture");
    }
    mGraph.addUse(mPass, {t.index, t.version, a, false, expected});
    return t;
}

BufferId PassBuilder::read(BufferId b, Access a) {
    if (!b.valid() || b.index >= mGraph.mResources.size() || mGraph.mResources[b.index].image) {
        throw GraphError("pass '" + mGraph.mPasses[mPass].name + "' reads an invalid buffer");
    }
    mGraph.addUse(mPass, {b.index, b.version, a, false, VK_FORMAT_UNDEFINED});
    return b;
}

TextureId PassBuilder::write(TextureId t, Access a, VkFormat expected) {
    if (!t.valid() || t.index >= mGraph.mResources.size() || !mGraph.mResources[t.index].image) {
        throw GraphError("pass '" + mGraph.mPasses[mPass].name + "' writes an invalid texture");
    }
    // A read-modify-write also reads the incoming version.
    if (accessInfo(a).reads) mGraph.addUse(mPass, {t.index, t.version, a, false, expected});
    auto& r = mGraph.mResources[t.index];
    r.versions = std::max(r.versions, t.version + 2);
    mGraph.addUse(mPass, {t.index, t.version + 1, a, true, expected});
    return {t.index, t.version + 1};
}

BufferId PassBuilder::write(BufferId b, Access a) {
    if (!b.valid() || b.index >= mGraph.mResources.size() || mGraph.mResources[b.index].image) {
        throw GraphError("pass '" + mGraph.mPasses[mPass].name + "' writes an invalid buffer");
    }
    if (accessInfo(a).reads)
        mGraph.addUse(mPass, {b.index, b.version, a, false, VK_FORMAT_UNDEFINED});
    auto& r = mGraph.mResources[b.index];
    r.versions = std::max(r.versions, b.version + 2);
    mGraph.addUse(mPass, {b.index, b.version + 1, a, true, VK_FORMAT_UNDEFINED});
    return {b.index, b.version + 1};
}

void PassBuilder::dependsOn(std::string_view passName) {
    mGraph.mPasses[mPass].after.emplace_back(mGraph.scopedName(passName));
}

void PassBuilder::sideEffect() {
    mGraph.mPasses[mPass].sideEffect = true;
}

std::pair<uint32_t, uint32_t> RenderGraph::textureExtent(const Resource& r) const {
    if (r.imported) return {r.importedTexture.width, r.importedTexture.height};
    if (r.texture.sizeMode == SizeMode::Absolute) {
        return {static_cast<uint32_t>(r.texture.width), static_cast<uint32_t>(r.texture.height)};
    }
    return {
        std::max(1u, static_cast<uint32_t>(r.texture.width * static_cast<float>(r.baseWidth))),
        std::max(1u, static_cast<uint32_t>(r.texture.height * static_cast<float>(r.baseHeight)))};
}

std::vector<uint32_t> CompiledGraph::order() const {
    std::vector<uint32_t> o;
    o.reserve(passes.size());
    for (const auto& p : passes)
        o.push_back(p.pass);
    return o;
}

// ---------------------------------------------------------------------------------------------
// Compile

CompiledGraph RenderGraph::compile() const {
    const detail::Declarations graph{mPasses, mResources, mSinks};
    const detail::Dependencies deps = detail::findDependencies(graph);
    const std::vector<bool> alive = detail::cullPasses(graph, deps);
    const std::vector<uint32_t> order = detail::orderPasses(graph, deps, alive);
    detail::ResourcePlan resources = detail::planLifetimes(graph, order);
    detail::BarrierPlan barriers = detail::planBarriers(graph, deps, order, resources.lifetimes);

    CompiledGraph out;
    out.passes.reserve(order.size());
    for (std::size_t pos = 0; pos < order.size(); ++pos) {
        out.passes.push_back({order[pos], std::move(barriers.beforePass[pos])});
    }
    for (uint32_t p = 0; p < alive.size(); ++p) {
        if (!alive[p]) out.culled.push_back(p);
    }
    out.lifetimes = std::move(resources.lifetimes);
    out.finalBarriers = std::move(barriers.final);
    out.imageUsage = std::move(resources.imageUsage);
    out.bufferUsage = std::move(resources.bufferUsage);
    return out;
}

// ---------------------------------------------------------------------------------------------
// Execute

const ResolvedTexture& PassResources::texture(TextureId t) const {
    return mTextures.at(t.index);
}
VkBuffer PassResources::buffer(BufferId b) const {
    return mBuffers.at(b.index).first;
}
VkBufferView PassResources::texelView(BufferId b) const {
    const VkBufferView v = b.index < mTexelViews.size() ? mTexelViews[b.index] : VK_NULL_HANDLE;
    if (v == VK_NULL_HANDLE) {
        throw GraphError("buffer " + std::to_string(b.index) +
                         " has no texel view: create it with a texel format and read it as "
                         "uniform");
    }
    return v;
}

VkDeviceSize PassResources::bufferSize(BufferId b) const {
    return mBuffers.at(b.index).second;
}

struct TransientPool::Impl {
    struct BufferEntry {
        vk::Buffer buffer;
        VkBufferUsageFlags usage = 0;
        std::optional<std::pair<VkFormat, vk::BufferView>> view;
    };
    std::map<std::string, vk::Image> images;
    std::map<std::string, BufferEntry> buffers;
    std::size_t created = 0;
};

TransientPool::TransientPool(vk::Context& ctx) : mCtx(ctx), mImpl(std::make_unique<Impl>()) {}
TransientPool::~TransientPool() = default;

std::size_t TransientPool::imageCount() const noexcept {
    return mImpl->images.size();
}

std::size_t TransientPool::created() const noexcept {
    return mImpl->created;
}

VkDeviceSize TransientPool::imageBytes(std::optional<VkExtent2D> extent) const noexcept {
    VkDeviceSize sum = 0;
    for (const auto& [name, image] : mImpl->images) {
        sum += hasExtent(image, extent) ? image.bytes() : 0;
    }
    return sum;
}

vk::Image& TransientPool::image(const std::string& name, uint32_t w, uint32_t h, VkFormat f,
                                VkImageUsageFlags usage) {
    auto it = mImpl->images.find(name);
    if (it != mImpl->images.end()) {
        const vk::ImageDesc& d = it->second.desc();
        if (d.width == w && d.height == h && d.format == f && (d.usage & usage) == usage) {
            return it->second;
        }
        mImpl->images.erase(it);
    }
    ++mImpl->created;
    return mImpl->images.emplace(name, vk::Image(mCtx, {w, h, f, usage, name})).first->second;
}

vk::Buffer& TransientPool::buffer(const std::string& name, VkDeviceSize size,
                                  VkBufferUsageFlags usage) {
    auto it = mImpl->buffers.find(name);
    if (it != mImpl->buffers.end() && it->second.buffer.size() == size &&
        (it->second.usage & usage) == usage) {
        return it->second.buffer;
    }
    if (it != mImpl->buffers.end()) {
        mImpl->buffers.erase(it); // its view goes with it
    }
    ++mImpl->created;
    Impl::BufferEntry e{vk::Buffer(mCtx, {size, usage, vk::MemoryUsage::GpuOnly, name}), usage,
                        std::nullopt};
    return mImpl->buffers.emplace(name, std::move(e)).first->second.buffer;
}

VkBufferView TransientPool::texelView(const std::string& name, VkFormat format) {
    const auto it = mImpl->buffers.find(name);
    if (it == mImpl->buffers.end()) {
        throw GraphError("no transient buffer '" + name + "' to view");
    }
    Impl::BufferEntry& e = it->second;
    if (!e.view || e.view->first != format) {
        e.view.emplace(format, vk::BufferView(mCtx, e.buffer, format));
    }
    return e.view->second.handle();
}

namespace {
void recordBarriers(VkCommandBuffer cmd, const std::vector<Barrier>& barriers,
                    const PassResources& res, const std::vector<VkImage>& images,
                    const std::vector<VkBuffer>& buffers) {
    (void)res;
    if (barriers.empty()) return;
    std::vector<VkImageMemoryBarrier2> ib;
    std::vector<VkBufferMemoryBarrier2> bb;
    for (const Barrier& b : barriers) {
        if (b.image) {
            VkImageMemoryBarrier2 x{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
            x.srcStageMask = b.srcStage;
            x.srcAccessMask = b.srcAccess;
            x.dstStageMask = b.dstStage;
            x.dstAccessMask = b.dstAccess;
            x.oldLayout = b.oldLayout;
            x.newLayout = b.newLayout;
            x.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            x.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            x.image = images[b.resource];
            x.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, b.layer, 1};
            ib.push_back(x);
        } else {
            VkBufferMemoryBarrier2 x{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
            x.srcStageMask = b.srcStage;
            x.srcAccessMask = b.srcAccess;
            x.dstStageMask = b.dstStage;
            x.dstAccessMask = b.dstAccess;
            x.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            x.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            x.buffer = buffers[b.resource];
            x.offset = 0;
            x.size = VK_WHOLE_SIZE;
            bb.push_back(x);
        }
    }
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = static_cast<uint32_t>(ib.size());
    dep.pImageMemoryBarriers = ib.data();
    dep.bufferMemoryBarrierCount = static_cast<uint32_t>(bb.size());
    dep.pBufferMemoryBarriers = bb.data();
    vkCmdPipelineBarrier2(cmd, &dep);
}
} // namespace

uint32_t RenderGraph::timestampCount(const CompiledGraph& compiled) noexcept {
    return std::max(2u, static_cast<uint32_t>(compiled.passes.size()) * 2);
}

RecordedFrame RenderGraph::record(const CompiledGraph& compiled, TransientPool& pool,
                                  vk::TimestampPool& timestamps, VkCommandBuffer cmd) {
    vk::Context& ctx = pool.context();
    if (compiled.lifetimes.size() != mResources.size()) {
        throw GraphError("recording a compiled plan of another graph");
    }
    const auto passTotal = static_cast<uint32_t>(compiled.passes.size());
    if (timestamps.capacity() < timestampCount(compiled)) {
        throw GraphError("timestamp pool holds " + std::to_string(timestamps.capacity()) +
                         " queries, the frame needs " + std::to_string(timestampCount(compiled)));
    }
    PassResources res;
    const std::size_t rc = mResources.size();
    res.mTextures.resize(rc);
    res.mBuffers.resize(rc);
    res.mTexelViews.resize(rc, VK_NULL_HANDLE);
    std::vector<VkImage> images(rc, VK_NULL_HANDLE);
    std::vector<VkBuffer> buffers(rc, VK_NULL_HANDLE);
    for (uint32_t r = 0; r < rc; ++r) {
        const Resource& x = mResources[r];
        if (compiled.lifetimes[r].firstPass < 0) continue; // unused this frame
        if (x.image) {
            const auto [w, h] = textureExtent(x);
            if (x.imported) {
                res.mTextures[r] = {
                    x.importedTexture.image, x.importedTexture.view, x.importedTexture.format, w, h,
                    x.importedTexture.layer};
            } else {
                vk::Image& img = pool.image(x.name, w, h, x.texture.format, compiled.imageUsage[r]);
                res.mTextures[r] = {img.handle(), img.view(), x.texture.format, w, h, 0};
            }
            images[r] = res.mTextures[r].image;
        } else {
            if (x.imported) {
                res.mBuffers[r] = {x.importedBuffer.buffer, x.importedBuffer.size};
            } else {
                vk::Buffer& buf = pool.buffer(x.name, x.buffer.size, compiled.bufferUsage[r]);
                res.mBuffers[r] = {buf.handle(), buf.size()};
                if (x.buffer.texelFormat != VK_FORMAT_UNDEFINED &&
                    (compiled.bufferUsage[r] & VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT) != 0) {
                    res.mTexelViews[r] = pool.texelView(x.name, x.buffer.texelFormat);
                }
            }
            buffers[r] = res.mBuffers[r].first;
        }
    }
    timestamps.reset();
    RecordedFrame frame;
    frame.mTimestamps = &timestamps;
    for (uint32_t i = 0; i < passTotal; ++i) {
        const CompiledPass& cp = compiled.passes[i];
        const Pass& pass = mPasses[cp.pass];
        ctx.beginLabel(cmd, pass.name);
        recordBarriers(cmd, cp.barriers, res, images, buffers);
        timestamps.write(cmd, 2 * i, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT);
        if (pass.execute) pass.execute(res, cmd);
        timestamps.write(cmd, 2 * i + 1, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT);
        ctx.endLabel(cmd);
        frame.mNames.push_back(pass.name);
    }
    recordBarriers(cmd, compiled.finalBarriers, res, images, buffers);
    return frame;
}

FrameTimings RecordedFrame::timings() const {
    FrameTimings t;
    const auto passTotal = static_cast<uint32_t>(mNames.size());
    if (mTimestamps == nullptr || passTotal == 0) return t;
    const std::vector<uint64_t> ticks = mTimestamps->read(2 * passTotal);
    if (ticks.size() < 2 * passTotal) return t;
    const double toMs = mTimestamps->tickToMs();
    for (uint32_t i = 0; i < passTotal; ++i) {
        t.passes.push_back(
            {mNames[i], static_cast<double>(ticks[2 * i + 1] - ticks[2 * i]) * toMs});
    }
    t.gpuMs = static_cast<double>(ticks[2 * passTotal - 1] - ticks[0]) * toMs;
    return t;
}

FrameTimings RenderGraph::executeAndWait(const CompiledGraph& compiled, TransientPool& pool) {
    vk::Context& ctx = pool.context();
    vk::TimestampPool timestamps(ctx, timestampCount(compiled));
    RecordedFrame frame;
    ctx.submitAndWait(
        [&](VkCommandBuffer cmd) { frame = record(compiled, pool, timestamps, cmd); });
    return frame.timings();
}

// ---------------------------------------------------------------------------------------------
// History and deferred release

void DeferredRelease::retire(std::shared_ptr<void> object, uint64_t frame) {
    if (object) mObjects.emplace_back(frame, std::move(object));
}

void DeferredRelease::collect(uint64_t frame) {
    std::erase_if(mObjects, [frame](const auto& o) { return o.first <= frame; });
}

struct HistoryPool::Entry {
    std::array<std::shared_ptr<vk::Image>, 2> images;
    int read = 0; // the image holding the last committed frame
    std::array<bool, 2> written{false, false};
    bool valid = false;
    uint32_t frames = 0;
};

HistoryPool::HistoryPool(vk::Context& ctx, DeferredRelease* release)
    : mCtx(ctx), mRelease(release) {}
HistoryPool::~HistoryPool() = default;

HistoryPool::Entry& HistoryPool::entry(const std::string& name, uint32_t w, uint32_t h,
                                       VkFormat f) {
    auto it = mEntries.find(name);
    if (it != mEntries.end()) {
        const vk::ImageDesc& d = it->second->images[0]->desc();
        if (d.width == w && d.height == h && d.format == f) return *it->second;
        // Resized: the old images may still be read by a frame in flight.
        if (mRelease) {
            for (auto& img : it->second->images)
                mRelease->retire(std::move(img), mFrame);
        }
        mEntries.erase(it);
    }
    auto e = std::make_unique<Entry>();
    for (int i = 0; i < 2; ++i) {
        e->images[static_cast<std::size_t>(i)] = std::make_shared<vk::Image>(
            mCtx, vk::ImageDesc{w, h, f,
                                VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                    VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                name + (i == 0 ? "#0" : "#1")});
    }
    return *mEntries.emplace(name, std::move(e)).first->second;
}

void HistoryPool::invalidate(std::string_view name) {
    if (auto it = mEntries.find(name); it != mEntries.end()) {
        it->second->valid = false;
        it->second->frames = 0;
    }
}

void HistoryPool::invalidatePrefix(std::string_view prefix) {
    for (auto& [name, e] : mEntries) {
        if (std::string_view(name).starts_with(prefix)) {
            e->valid = false;
            e->frames = 0;
        }
    }
}

void HistoryPool::invalidateAll() {
    for (auto& [name, e] : mEntries) {
        e->valid = false;
        e->frames = 0;
    }
}

uint32_t HistoryPool::frames(std::string_view name) const {
    const auto it = mEntries.find(name);
    return it == mEntries.end() ? 0 : it->second->frames;
}

bool HistoryPool::holds(std::string_view name, uint32_t width, uint32_t height,
                        VkFormat format) const {
    const auto it = mEntries.find(name);
    if (it == mEntries.end() || !it->second->valid) {
        return false;
    }
    const vk::ImageDesc& d = it->second->images[0]->desc();
    return d.width == width && d.height == height && d.format == format;
}

VkDeviceSize HistoryPool::imageBytes(std::optional<VkExtent2D> extent) const noexcept {
    VkDeviceSize sum = 0;
    for (const auto& [name, e] : mEntries) {
        for (const std::shared_ptr<vk::Image>& image : e->images) {
            sum += image && hasExtent(*image, extent) ? image->bytes() : 0;
        }
    }
    return sum;
}

void HistoryPool::commit(const RenderGraph& graph) {
    for (const RenderGraph::HistoryUse& u : graph.mHistories) {
        if (u.pool != this) continue;
        const auto it = mEntries.find(u.name);
        if (it == mEntries.end()) continue; // resized away since
        Entry& e = *it->second;
        e.frames = e.valid ? e.frames + 1 : 1;
        e.written[static_cast<std::size_t>(u.writeIndex)] = true;
        e.read = u.writeIndex;
        e.valid = true;
    }
}

TextureId RenderGraph::importHistoryImage(const HistoryPool::Entry& e, int index,
                                          std::string_view name, VkFormat format, uint32_t width,
                                          uint32_t height) {
    const vk::Image& img = *e.images[static_cast<std::size_t>(index)];
    return importTexture(name, {img.handle(), img.view(), format, width, height,
                                e.written[static_cast<std::size_t>(index)]
                                    ? std::optional(Access::StorageWrite)
                                    : std::nullopt,
                                // Whatever reads it this frame, leave it in GENERAL, the layout
                                // the next frame's import declares.
                                Access::StorageRead});
}

HistoryTextures RenderGraph::importHistory(HistoryPool& pool, std::string_view unscoped,
                                           VkFormat format, uint32_t width, uint32_t height) {
    const std::string name = scopedName(unscoped);
    HistoryPool::Entry& e = pool.entry(name, width, height, format);
    const int readIndex = e.read, writeIndex = 1 - e.read;
    const std::string base(unscoped);
    HistoryTextures h;
    h.valid = e.valid;
    h.previous = importHistoryImage(e, readIndex, base + ".previous", format, width, height);
    h.next = importHistoryImage(e, writeIndex, base + ".next", format, width, height);
    mHistories.push_back({&pool, name, writeIndex});
    return h;
}

HistoryTextures RenderGraph::readHistory(HistoryPool& pool, std::string_view unscoped,
                                         VkFormat format, uint32_t width, uint32_t height) {
    const HistoryPool::Entry& e = pool.entry(scopedName(unscoped), width, height, format);
    HistoryTextures h;
    h.valid = e.valid;
    h.previous =
        importHistoryImage(e, e.read, std::string(unscoped) + ".previous", format, width, height);
    return h;
}

// ---------------------------------------------------------------------------------------------
// Graphviz

std::string RenderGraph::toDot(const CompiledGraph& compiled) const {
    std::ostringstream os;
    os << "digraph gazetrace {\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n";
    std::vector<int> position(mPasses.size(), -1);
    for (std::size_t i = 0; i < compiled.passes.size(); ++i) {
        position[compiled.passes[i].pass] = static_cast<int>(i);
    }
    for (uint32_t p = 0; p < mPasses.size(); ++p) {
        os << "  p" << p << " [shape=box, style=\"" << (position[p] < 0 ? "dashed" : "filled")
           << "\", fillcolor=\"#ffd27f\", label=\"" << mPasses[p].name;
        if (position[p] >= 0) {
            os << "\\n#" << position[p] << ", " << compiled.passes[position[p]].barriers.size()
               << " barrier(s)";
        } else {
            os << "\\n(culled)";
        }
        os << "\"];\n";
    }
    for (uint32_t r = 0; r < mResources.size(); ++r) {
        const Resource& x = mResources[r];
        for (uint32_t v = 0; v < x.versions; ++v) {
            os << "  r" << r << "_" << v << " [shape=ellipse, style=filled, fillcolor=\""
               << (x.imported ? "#9fd0ff" : "#c8f0c8") << "\", label=\"" << x.name << " v" << v
               << "\"];\n";
        }
    }
    for (uint32_t p = 0; p < mPasses.size(); ++p) {
        for (const Use& u : mPasses[p].uses) {
            if (u.write) {
                os << "  p" << p << " -> r" << u.resource << "_" << u.version << " [label=\""
                   << toString(u.access) << "\", color=red];\n";
            } else {
                os << "  r" << u.resource << "_" << u.version << " -> p" << p << " [label=\""
                   << toString(u.access) << "\"];\n";
            }
        }
    }
    os << "}\n";
    return os.str();
}

} // namespace gt::rg
