#include "action_sets.hpp"

#include <cstring>

#include "core/error.hpp"
#include "core/log.hpp"
#include "xr_error.hpp"

namespace gt::xr {

namespace {
void copyName(char* out, std::size_t size, const std::string& name) {
    std::strncpy(out, name.c_str(), size - 1);
    out[size - 1] = '\0';
}
} // namespace

ActionSets::ActionSets(Session& session) : mSession(session) {}

ActionSets::~ActionSets() {
    const auto scope = mSession.context().runtimeCalls();
    for (const XrActionSet set : mSets) {
        xrDestroyActionSet(set); // and its actions
    }
}

XrPath ActionSets::path(const std::string& text) const {
    XrPath p = XR_NULL_PATH;
    GT_XR_CHECK(xrStringToPath(mSession.runtime().instance(), text.c_str(), &p));
    return p;
}

XrActionSet ActionSets::createSet(const std::string& name, const std::string& localizedName) {
    if (mAttached) {
        throw Error("OpenXR: action set '" + name + "' created after attaching");
    }
    const auto scope = mSession.context().runtimeCalls();
    XrActionSetCreateInfo info{XR_TYPE_ACTION_SET_CREATE_INFO};
    copyName(info.actionSetName, XR_MAX_ACTION_SET_NAME_SIZE, name);
    copyName(info.localizedActionSetName, XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE, localizedName);
    XrActionSet set = XR_NULL_HANDLE;
    GT_XR_CHECK(xrCreateActionSet(mSession.runtime().instance(), &info, &set));
    mSets.push_back(set);
    return set;
}

XrAction ActionSets::createAction(XrActionSet set, XrActionType type, const std::string& name,
                                  const std::string& localizedName) {
    const auto scope = mSession.context().runtimeCalls();
    XrActionCreateInfo info{XR_TYPE_ACTION_CREATE_INFO};
    info.actionType = type;
    copyName(info.actionName, XR_MAX_ACTION_NAME_SIZE, name);
    copyName(info.localizedActionName, XR_MAX_LOCALIZED_ACTION_NAME_SIZE, localizedName);
    XrAction action = XR_NULL_HANDLE;
    GT_XR_CHECK(xrCreateAction(set, &info, &action));
    return action;
}

void ActionSets::suggest(const std::string& profile, XrAction action, const std::string& binding) {
    if (mAttached) {
        throw Error("OpenXR: binding " + binding + " suggested after attaching");
    }
    mBindings[profile].push_back({action, path(binding)});
}

void ActionSets::attach() {
    if (mAttached) {
        return;
    }
    const auto scope = mSession.context().runtimeCalls();
    for (const auto& [profile, bindings] : mBindings) {
        XrInteractionProfileSuggestedBinding suggested{
            XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
        suggested.interactionProfile = path(profile);
        suggested.countSuggestedBindings = static_cast<uint32_t>(bindings.size());
        suggested.suggestedBindings = bindings.data();
        const XrResult r =
            xrSuggestInteractionProfileBindings(mSession.runtime().instance(), &suggested);
        if (r == XR_ERROR_PATH_UNSUPPORTED) {
            // A profile this runtime does not offer: the others still bind.
            log::info("xr: the runtime does not offer " + profile);
            mSkipped.push_back(profile);
            continue;
        }
        GT_XR_CHECK(r);
        mSuggested.push_back(profile);
    }
    if (!mSets.empty()) {
        XrSessionActionSetsAttachInfo info{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
        info.countActionSets = static_cast<uint32_t>(mSets.size());
        info.actionSets = mSets.data();
        GT_XR_CHECK(xrAttachSessionActionSets(mSession.handle(), &info));
    }
    mAttached = true;
}

bool ActionSets::sync() {
    if (mSets.empty()) {
        return false;
    }
    attach();
    const auto scope = mSession.context().runtimeCalls();
    std::vector<XrActiveActionSet> active;
    active.reserve(mSets.size());
    for (const XrActionSet set : mSets) {
        active.push_back({set, XR_NULL_PATH});
    }
    XrActionsSyncInfo info{XR_TYPE_ACTIONS_SYNC_INFO};
    info.countActiveActionSets = static_cast<uint32_t>(active.size());
    info.activeActionSets = active.data();
    const XrResult r = xrSyncActions(mSession.handle(), &info);
    GT_XR_CHECK(r);
    ++mSyncs;
    if (r == XR_SESSION_NOT_FOCUSED) {
        return false; // input goes elsewhere
    }
    ++mFocusedSyncs;
    return true;
}

} // namespace gt::xr
