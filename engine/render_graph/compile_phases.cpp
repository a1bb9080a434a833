#include "render_graph/compile_phases.hpp"

#include <algorithm>
#include <optional>
#include <queue>
#include <string>

#include "core/error.hpp"

namespace gt::rg::detail {

namespace {

const char* formatName(VkFormat f) {
    switch (f) {
    case VK_FORMAT_R8G8B8A8_UNORM:
        return "R8G8B8A8_UNORM";
    case VK_FORMAT_R8G8B8A8_SRGB:
        return "R8G8B8A8_SRGB";
    case VK_FORMAT_B8G8R8A8_UNORM:
        return "B8G8R8A8_UNORM";
    case VK_FORMAT_R16G16B16A16_SFLOAT:
        return "R16G16B16A16_SFLOAT";
    case VK_FORMAT_R32G32B32A32_SFLOAT:
        return "R32G32B32A32_SFLOAT";
    case VK_FORMAT_R32G32_SFLOAT:
        return "R32G32_SFLOAT";
    case VK_FORMAT_R32_SFLOAT:
        return "R32_SFLOAT";
    case VK_FORMAT_R32_UINT:
        return "R32_UINT";
    default:
        return "VkFormat(other)";
    }
}

// Who writes each (resource, version)? Checks the formats passes expect on the way.
std::map<VersionKey, uint32_t> findWriters(const Declarations& g) {
    std::map<VersionKey, uint32_t> writer;
    for (uint32_t p = 0; p < g.passes.size(); ++p) {
        for (const Use& u : g.passes[p].uses) {
            const Resource& r = g.resources[u.resource];
            if (u.expected != VK_FORMAT_UNDEFINED && r.image && r.texture.format != u.expected) {
                throw GraphError("pass '" + g.passes[p].name + "' expects " +
                                 formatName(u.expected) + " for '" + r.name + "', which is " +
                                 formatName(r.texture.format));
            }
            if (!u.write) continue;
            auto [it, inserted] = writer.emplace(std::make_pair(u.resource, u.version), p);
            if (!inserted && it->second != p) {
                throw GraphError("passes '" + g.passes[it->second].name + "' and '" +
                                 g.passes[p].name + "' both write '" + r.name +
                                 "' without an order between them (write through a stale handle)");
            }
        }
    }
    return writer;
}

uint32_t passNamed(const Declarations& g, uint32_t from, const std::string& name) {
    const auto it = std::find_if(g.passes.begin(), g.passes.end(),
                                 [&](const Pass& q) { return q.name == name; });
    if (it == g.passes.end()) {
        throw GraphError("pass '" + g.passes[from].name + "' depends on unknown pass '" + name +
                         "'");
    }
    return static_cast<uint32_t>(it - g.passes.begin());
}

// Whether `p` needs `q` to run: q produces a version p reads (or the version p overwrites), or
// p names q in dependsOn().
bool needs(const Declarations& g, const Dependencies& deps, uint32_t p, uint32_t q) {
    const Pass& pass = g.passes[p];
    if (std::find(pass.after.begin(), pass.after.end(), g.passes[q].name) != pass.after.end()) {
        return true;
    }
    for (const Use& u : pass.uses) {
        if (u.write && u.version < 2) continue;
        const uint32_t v = u.write ? u.version - 1 : u.version;
        const auto w = deps.writer.find({u.resource, v});
        if (w != deps.writer.end() && w->second == q) return true;
    }
    return false;
}

bool isCullRoot(const Declarations& g, const Dependencies& deps, uint32_t p) {
    bool root = g.passes[p].sideEffect;
    for (const Use& u : g.passes[p].uses)
        root |= u.write && g.resources[u.resource].imported;
    for (const Sink& k : g.sinks) {
        const auto w = deps.writer.find({k.resource, k.version});
        root |= w != deps.writer.end() && w->second == p;
    }
    return root;
}

void addUsage(ResourcePlan& plan, const Resource& res, uint32_t r, Access a) {
    if (res.image) {
        switch (a) {
        case Access::StorageRead:
        case Access::StorageWrite:
        case Access::StorageReadWrite:
            plan.imageUsage[r] |= VK_IMAGE_USAGE_STORAGE_BIT;
            break;
        case Access::SampledCompute:
        case Access::UniformRead:
            plan.imageUsage[r] |= VK_IMAGE_USAGE_SAMPLED_BIT;
            break;
        case Access::TransferSrc:
            plan.imageUsage[r] |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
            break;
        case Access::TransferDst:
            plan.imageUsage[r] |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
            break;
        case Access::ColorAttachment:
            plan.imageUsage[r] |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
            break;
        default:
            break;
        }
        return;
    }
    switch (a) {
    case Access::UniformRead:
        plan.bufferUsage[r] |=
            VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
        break;
    case Access::TransferSrc:
    case Access::TransferDst:
    case Access::HostRead:
        break;
    default:
        plan.bufferUsage[r] |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        break;
    }
}

std::optional<Access> initialAccess(const Resource& r) {
    return r.image ? r.importedTexture.initialAccess : r.importedBuffer.initialAccess;
}

std::optional<Access> finalAccess(const Resource& r) {
    return r.image ? r.importedTexture.finalAccess : r.importedBuffer.finalAccess;
}

// Tracks per resource the last write and the reads since, walking the passes in execution
// order, and places the barrier each new access needs (none when an earlier barrier already
// made the write visible to it).
class BarrierTracker {
public:
    explicit BarrierTracker(std::span<const Resource> resources);
    void access(std::vector<Barrier>& list, uint32_t r, const AccessInfo& use);

private:
    struct State {
        VkPipelineStageFlags2 writeStage = VK_PIPELINE_STAGE_2_NONE;
        VkAccessFlags2 writeAccess = VK_ACCESS_2_NONE;
        VkPipelineStageFlags2 readStages = VK_PIPELINE_STAGE_2_NONE; // since the last write
        VkPipelineStageFlags2 visibleStages = VK_PIPELINE_STAGE_2_NONE;
        VkAccessFlags2 visibleAccess = VK_ACCESS_2_NONE;
        VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    };
    std::span<const Resource> mResources;
    std::vector<State> mState;
};

BarrierTracker::BarrierTracker(std::span<const Resource> resources)
    : mResources(resources), mState(resources.size()) {
    for (std::size_t r = 0; r < resources.size(); ++r) {
        const Resource& res = resources[r];
        const std::optional<Access> init = initialAccess(res);
        State& s = mState[r];
        if (res.imported && init) {
            const AccessInfo ai = accessInfo(*init);
            s.layout = res.image ? ai.layout : VK_IMAGE_LAYOUT_UNDEFINED;
            // Whatever happened before this frame is treated as a write to wait for.
            s.writeStage = ai.stage == VK_PIPELINE_STAGE_2_NONE
                               ? VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT
                               : ai.stage;
            s.writeAccess = ai.writes ? ai.access : VK_ACCESS_2_NONE;
        } else if (res.imported && res.image &&
                   res.importedTexture.acquireStage != VK_PIPELINE_STAGE_2_NONE) {
            s.writeStage = res.importedTexture.acquireStage; // the semaphore wait
        }
    }
}

void BarrierTracker::access(std::vector<Barrier>& list, uint32_t r, const AccessInfo& use) {
    State& s = mState[r];
    const Resource& res = mResources[r];
    const bool image = res.image;
    const bool layoutChange = image && s.layout != use.layout;
    Barrier b;
    b.resource = r;
    b.image = image;
    b.layer = res.imported ? res.importedTexture.layer : 0;
    b.oldLayout = s.layout;
    b.newLayout = image ? use.layout : VK_IMAGE_LAYOUT_UNDEFINED;
    b.dstStage =
        use.stage == VK_PIPELINE_STAGE_2_NONE ? VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT : use.stage;
    b.dstAccess = use.access;
    bool needed = layoutChange;
    if (use.writes) {
        // WAW: wait for and make available the last write; WAR: wait for the readers.
        if (s.writeStage != VK_PIPELINE_STAGE_2_NONE) {
            b.srcStage |= s.writeStage;
            b.srcAccess |= s.writeAccess;
            needed = true;
        }
        if (s.readStages != VK_PIPELINE_STAGE_2_NONE) {
            b.srcStage |= s.readStages;
            needed = true;
        }
    } else if (s.writeStage != VK_PIPELINE_STAGE_2_NONE) {
        // RAW: needed unless an earlier barrier already made the write visible here.
        const bool covered = (s.visibleStages & use.stage) == use.stage &&
                             (s.visibleAccess & use.access) == use.access;
        if (!covered || layoutChange) {
            b.srcStage |= s.writeStage;
            b.srcAccess |= s.writeAccess;
            needed = true;
        }
    }
    if (layoutChange) {
        // The transition itself is a write: order it after every earlier access.
        b.srcStage |= s.writeStage | s.readStages;
        b.srcAccess |= s.writeAccess;
    }
    if (needed) list.push_back(b);
    // Update the tracked state.
    if (image) s.layout = use.layout;
    if (use.writes || layoutChange) {
        s.writeStage = use.writes ? use.stage : b.dstStage;
        s.writeAccess = use.writes ? use.access : VK_ACCESS_2_NONE;
        s.readStages = use.writes ? VK_PIPELINE_STAGE_2_NONE : use.stage;
        s.visibleStages = use.writes ? VK_PIPELINE_STAGE_2_NONE : use.stage;
        s.visibleAccess = use.writes ? VK_ACCESS_2_NONE : use.access;
    } else {
        s.readStages |= use.stage;
        if (needed) {
            s.visibleStages |= use.stage;
            s.visibleAccess |= use.access;
        }
    }
}

// The uses of one resource within a pass merged into one access (a read-modify-write declares
// a read and a write); one image in two layouts at once is an error.
std::map<uint32_t, AccessInfo> mergedAccesses(const Declarations& g, const Pass& pass) {
    std::map<uint32_t, AccessInfo> merged;
    for (const Use& u : pass.uses) {
        const AccessInfo ai = accessInfo(u.access);
        auto [it, inserted] = merged.emplace(u.resource, ai);
        if (inserted) continue;
        if (g.resources[u.resource].image && it->second.layout != ai.layout) {
            throw GraphError("pass '" + pass.name + "' uses '" + g.resources[u.resource].name +
                             "' in two layouts at once (" + toString(u.access) + ")");
        }
        it->second.stage |= ai.stage;
        it->second.access |= ai.access;
        it->second.writes |= ai.writes;
        it->second.reads |= ai.reads;
    }
    return merged;
}

} // namespace

Dependencies findDependencies(const Declarations& g) {
    const auto passCount = static_cast<uint32_t>(g.passes.size());
    Dependencies d{findWriters(g), std::vector<std::set<uint32_t>>(passCount)};
    std::map<VersionKey, std::vector<uint32_t>> readers;
    for (uint32_t p = 0; p < passCount; ++p) {
        for (const Use& u : g.passes[p].uses) {
            if (u.write) {
                if (u.version >= 2) {
                    auto w = d.writer.find({u.resource, u.version - 1});
                    if (w != d.writer.end() && w->second != p) d.preds[p].insert(w->second);
                }
                continue;
            }
            const Resource& r = g.resources[u.resource];
            auto w = d.writer.find({u.resource, u.version});
            if (w == d.writer.end()) {
                if (!(r.imported && u.version == 0)) {
                    throw GraphError("pass '" + g.passes[p].name + "' reads '" + r.name +
                                     "', which nothing writes");
                }
            } else if (w->second != p) {
                d.preds[p].insert(w->second);
            }
            readers[{u.resource, u.version}].push_back(p);
        }
        for (const std::string& name : g.passes[p].after)
            d.preds[p].insert(passNamed(g, p, name));
    }
    for (const auto& [key, list] : readers) {
        auto w = d.writer.find({key.first, key.second + 1});
        if (w == d.writer.end()) continue;
        for (uint32_t reader : list) {
            if (reader != w->second) d.preds[w->second].insert(reader);
        }
    }
    return d;
}

std::vector<bool> cullPasses(const Declarations& g, const Dependencies& deps) {
    const auto passCount = static_cast<uint32_t>(g.passes.size());
    std::vector<bool> alive(passCount, false);
    std::vector<uint32_t> stack;
    for (uint32_t p = 0; p < passCount; ++p) {
        if (isCullRoot(g, deps, p)) {
            alive[p] = true;
            stack.push_back(p);
        }
    }
    while (!stack.empty()) {
        const uint32_t p = stack.back();
        stack.pop_back();
        for (uint32_t q : deps.preds[p]) {
            if (!alive[q] && needs(g, deps, p, q)) {
                alive[q] = true;
                stack.push_back(q);
            }
        }
    }
    return alive;
}

std::vector<uint32_t> orderPasses(const Declarations& g, const Dependencies& deps,
                                  const std::vector<bool>& alive) {
    const auto passCount = static_cast<uint32_t>(g.passes.size());
    std::vector<uint32_t> indegree(passCount, 0);
    std::vector<std::vector<uint32_t>> succs(passCount);
    for (uint32_t p = 0; p < passCount; ++p) {
        if (!alive[p]) continue;
        for (uint32_t q : deps.preds[p]) {
            if (!alive[q]) continue;
            ++indegree[p];
            succs[q].push_back(p);
        }
    }
    std::priority_queue<uint32_t, std::vector<uint32_t>, std::greater<>> ready;
    for (uint32_t p = 0; p < passCount; ++p) {
        if (alive[p] && indegree[p] == 0) ready.push(p);
    }
    std::vector<uint32_t> order;
    while (!ready.empty()) {
        const uint32_t p = ready.top();
        ready.pop();
        order.push_back(p);
        for (uint32_t s : succs[p]) {
            if (--indegree[s] == 0) ready.push(s);
        }
    }
    const auto aliveCount = static_cast<std::size_t>(std::count(alive.begin(), alive.end(), true));
    if (order.size() != aliveCount) {
        std::string names;
        for (uint32_t p = 0; p < passCount; ++p) {
            if (alive[p] && indegree[p] > 0)
                names += (names.empty() ? "'" : ", '") + g.passes[p].name + "'";
        }
        throw GraphError("render graph has a cycle through passes " + names);
    }
    return order;
}

ResourcePlan planLifetimes(const Declarations& g, std::span<const uint32_t> order) {
    const std::size_t rc = g.resources.size();
    ResourcePlan plan{std::vector<Lifetime>(rc), std::vector<VkImageUsageFlags>(rc, 0),
                      std::vector<VkBufferUsageFlags>(rc, 0)};
    for (std::size_t pos = 0; pos < order.size(); ++pos) {
        for (const Use& u : g.passes[order[pos]].uses) {
            addUsage(plan, g.resources[u.resource], u.resource, u.access);
            Lifetime& lt = plan.lifetimes[u.resource];
            if (lt.firstPass < 0) lt.firstPass = static_cast<int>(pos);
            lt.lastPass = static_cast<int>(pos);
        }
    }
    // The accesses after the frame (an import's final access, a sink's) need their usage too.
    for (uint32_t r = 0; r < rc; ++r) {
        const Resource& res = g.resources[r];
        const std::optional<Access> fin = finalAccess(res);
        if (res.imported && fin && plan.lifetimes[r].firstPass >= 0) addUsage(plan, res, r, *fin);
    }
    for (const Sink& k : g.sinks) {
        if (plan.lifetimes[k.resource].firstPass < 0) continue; // an untouched import
        addUsage(plan, g.resources[k.resource], k.resource, k.access);
    }
    return plan;
}

BarrierPlan planBarriers(const Declarations& g, const Dependencies& deps,
                         std::span<const uint32_t> order, std::span<const Lifetime> lifetimes) {
    BarrierPlan plan;
    plan.beforePass.resize(order.size());
    BarrierTracker tracker(g.resources);
    for (std::size_t pos = 0; pos < order.size(); ++pos) {
        for (const auto& [r, ai] : mergedAccesses(g, g.passes[order[pos]]))
            tracker.access(plan.beforePass[pos], r, ai);
    }
    for (uint32_t r = 0; r < g.resources.size(); ++r) {
        const Resource& res = g.resources[r];
        const std::optional<Access> fin = finalAccess(res);
        if (res.imported && fin && lifetimes[r].firstPass >= 0) {
            tracker.access(plan.final, r, accessInfo(*fin));
        }
    }
    for (const Sink& k : g.sinks) {
        const Resource& res = g.resources[k.resource];
        const auto w = deps.writer.find({k.resource, k.version});
        if (w == deps.writer.end() && !(res.imported && k.version == 0)) {
            throw GraphError("sink of '" + res.name + "', a version nothing writes");
        }
        if (lifetimes[k.resource].firstPass < 0) continue; // an untouched import
        tracker.access(plan.final, k.resource, accessInfo(k.access));
    }
    return plan;
}

} // namespace gt::rg::detail
