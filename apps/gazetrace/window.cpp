#include "window.hpp"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>

#include "core/error.hpp"

namespace gt::app {

namespace {
std::string glfwLastError() {
    const char* what = nullptr;
    glfwGetError(&what);
    return what ? what : "unknown reason";
}
} // namespace

Window::Window(const std::string& title, uint32_t width, uint32_t height) {
    if (glfwInit() != GLFW_TRUE) {
        throw Error("cannot open a window: " + glfwLastError() +
                    " (no display? set DISPLAY or run under xvfb-run)");
    }
    if (glfwVulkanSupported() != GLFW_TRUE) {
        glfwTerminate();
        throw Error("cannot open a window: the window system has no Vulkan presentation");
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    mWindow = glfwCreateWindow(static_cast<int>(width), static_cast<int>(height), title.c_str(),
                               nullptr, nullptr);
    if (mWindow == nullptr) {
        const std::string why = glfwLastError();
        glfwTerminate();
        throw Error("cannot open a window: " + why);
    }
    glfwSetWindowUserPointer(mWindow, this);
    glfwSetFramebufferSizeCallback(mWindow, [](GLFWwindow* w, int, int) {
        static_cast<Window*>(glfwGetWindowUserPointer(w))->mResized = true;
    });
    glfwSetKeyCallback(mWindow, [](GLFWwindow* w, int key, int, int action, int) {
        if (action == GLFW_PRESS) {
            static_cast<Window*>(glfwGetWindowUserPointer(w))->mPressed.push_back(key);
        }
    });
}

Window::~Window() {
    glfwDestroyWindow(mWindow);
    glfwTerminate();
}

std::vector<std::string> Window::requiredInstanceExtensions() const {
    uint32_t n = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&n);
    if (names == nullptr) throw Error("the window system names no Vulkan surface extensions");
    return {names, names + n};
}

VkSurfaceKHR Window::createSurface(VkInstance instance) const {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    const VkResult r = glfwCreateWindowSurface(instance, mWindow, nullptr, &surface);
    if (r != VK_SUCCESS) throw VulkanError(r, "glfwCreateWindowSurface", __FILE__, __LINE__);
    return surface;
}

void Window::poll() {
    glfwPollEvents();
}
void Window::waitEvents() {
    glfwWaitEventsTimeout(0.1);
}
bool Window::shouldClose() const {
    return glfwWindowShouldClose(mWindow) == GLFW_TRUE;
}
void Window::requestClose() {
    glfwSetWindowShouldClose(mWindow, GLFW_TRUE);
}

VkExtent2D Window::framebufferSize() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(mWindow, &w, &h);
    return {static_cast<uint32_t>(std::max(w, 0)), static_cast<uint32_t>(std::max(h, 0))};
}

bool Window::takeResized() {
    const bool r = mResized;
    mResized = false;
    return r;
}

glm::ivec2 Window::position() const {
    int x = 0, y = 0;
    glfwGetWindowPos(mWindow, &x, &y);
    return {x, y};
}

void Window::setSize(uint32_t width, uint32_t height) {
    glfwSetWindowSize(mWindow, static_cast<int>(width), static_cast<int>(height));
}

glm::vec2 Window::cursor() const {
    double x = 0, y = 0;
    glfwGetCursorPos(mWindow, &x, &y);
    return {static_cast<float>(x), static_cast<float>(y)};
}

bool Window::key(int glfwKey) const {
    return glfwGetKey(mWindow, glfwKey) == GLFW_PRESS;
}

bool Window::mouseButton(int glfwButton) const {
    return glfwGetMouseButton(mWindow, glfwButton) == GLFW_PRESS;
}

std::vector<int> Window::takePressedKeys() {
    std::vector<int> keys;
    keys.swap(mPressed);
    return keys;
}

} // namespace gt::app
