#pragma once
// A desktop window for the demo (GLFW): its Vulkan surface, framebuffer size, and the input the
// demo reads each frame. One per process; RAII for GLFW itself and the window.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

struct GLFWwindow;

namespace gt::app {

class Window {
public:
    // Throws gt::Error with one line when no window can be opened (no display, no Vulkan
    // presentation support in the window system).
    Window(const std::string& title, uint32_t width, uint32_t height);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    [[nodiscard]] std::vector<std::string> requiredInstanceExtensions() const;
    [[nodiscard]] VkSurfaceKHR createSurface(VkInstance instance) const;
    [[nodiscard]] GLFWwindow* handle() const noexcept { return mWindow; }

    void poll();       // processes pending events
    void waitEvents(); // sleeps until an event arrives (while minimised)
    [[nodiscard]] bool shouldClose() const;
    void requestClose();
    [[nodiscard]] VkExtent2D framebufferSize() const;
    // The framebuffer size changed since the last call.
    [[nodiscard]] bool takeResized();
    // Top-left of the window on the screen, in pixels (screen gaze -> window gaze).
    [[nodiscard]] glm::ivec2 position() const;
    void setSize(uint32_t width, uint32_t height);

    [[nodiscard]] glm::vec2 cursor() const; // window pixels
    [[nodiscard]] bool key(int glfwKey) const;
    [[nodiscard]] bool mouseButton(int glfwButton) const;
    // Keys pressed since the last call (GLFW key codes), for one-shot switches.
    [[nodiscard]] std::vector<int> takePressedKeys();

private:
    GLFWwindow* mWindow = nullptr;
    bool mResized = false;
    std::vector<int> mPressed;
};

} // namespace gt::app
