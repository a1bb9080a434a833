#pragma once
// The session's action sets, attached and synced together. OpenXR lets an application attach
// action sets to a session once (xrAttachSessionActionSets: XR_ERROR_ACTIONSETS_ALREADY_ATTACHED
// on a second call) and replaces an interaction profile's suggested bindings on every call to
// xrSuggestInteractionProfileBindings for it; so each input (eye gaze, the response buttons)
// creates its set and actions here, its bindings are collected per profile, and attach() suggests
// each profile once and attaches every set in one call. sync() is the frame's one xrSyncActions
// over all of them; the inputs then read their actions' states.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "openxr.hpp"
#include "xr_session.hpp"

namespace gt::xr {

class ActionSets {
public:
    // `session` must outlive this.
    explicit ActionSets(Session& session);
    // Destroys every set created here (with its actions).
    ~ActionSets();
    ActionSets(const ActionSets&) = delete;
    ActionSets& operator=(const ActionSets&) = delete;

    // A new action set (before attach()).
    [[nodiscard]] XrActionSet createSet(const std::string& name, const std::string& localizedName);
    // A new action without subaction paths in `set` (before attach()).
    [[nodiscard]] XrAction createAction(XrActionSet set, XrActionType type, const std::string& name,
                                        const std::string& localizedName);
    // Binds `action` to `binding` (an input path) on `profile`, suggested at attach().
    void suggest(const std::string& profile, XrAction action, const std::string& binding);

    // Suggests each profile's bindings (a profile the runtime does not know is left out and
    // named in skippedProfiles()) and attaches every set in one call. Once; sync() calls it
    // when it was not called.
    void attach();
    // One xrSyncActions over every set. False when input goes elsewhere (the session is not
    // FOCUSED): the actions' states are then inactive. Nothing is called without a set.
    bool sync();

    [[nodiscard]] bool attached() const noexcept { return mAttached; }
    [[nodiscard]] std::size_t setCount() const noexcept { return mSets.size(); }
    // The frames synced so far, and of them those that reached the application.
    [[nodiscard]] uint32_t syncs() const noexcept { return mSyncs; }
    [[nodiscard]] uint32_t focusedSyncs() const noexcept { return mFocusedSyncs; }
    [[nodiscard]] const std::vector<std::string>& suggestedProfiles() const noexcept {
        return mSuggested;
    }
    [[nodiscard]] const std::vector<std::string>& skippedProfiles() const noexcept {
        return mSkipped;
    }
    [[nodiscard]] Session& session() const noexcept { return mSession; }
    [[nodiscard]] XrPath path(const std::string& text) const;

private:
    Session& mSession;
    std::vector<XrActionSet> mSets;
    std::map<std::string, std::vector<XrActionSuggestedBinding>> mBindings;
    std::vector<std::string> mSuggested, mSkipped;
    bool mAttached = false;
    uint32_t mSyncs = 0, mFocusedSyncs = 0;
};

} // namespace gt::xr
