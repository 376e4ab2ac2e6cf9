// The window: GLFW input mapped onto ViewerSession, the session's images presented each frame.
#include "viewer/viewer.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "core/image_io.h"
#include "engine/vk/context.h"
#include "eval/experiment.h"
#include "eval/strategies.h"
#include "viewer/presenter.h"
#include "viewer/session.h"

namespace aamap {
namespace {

std::string gGlfwError;

void glfwError(int code, const char* message) { gGlfwError = fmt::format("{} (GLFW error {:#x})", message, code); }

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

// GLFW owns a process-wide state: terminate it on every way out.
struct GlfwLibrary {
    GlfwLibrary() {
        glfwSetErrorCallback(glfwError);
        if (env("DISPLAY").empty() && env("WAYLAND_DISPLAY").empty())
            throw EnvironmentError(
                "aamap view needs a display: DISPLAY (and WAYLAND_DISPLAY) is not set. On a machine without "
                "one, run it under a virtual X server: xvfb-run -a aamap view CONFIG");
        if (!glfwInit())
            throw EnvironmentError(fmt::format("aamap view cannot open the display '{}': {}", env("DISPLAY"), gGlfwError));
        if (!glfwVulkanSupported()) {
            glfwTerminate();
            throw EnvironmentError("GLFW finds no Vulkan loader with window-system support (Debian: libvulkan1)");
        }
    }
    ~GlfwLibrary() { glfwTerminate(); }
};

struct Window {
    GLFWwindow* handle = nullptr;
    ~Window() {
        if (handle) glfwDestroyWindow(handle);
    }
};

// The render the viewer traces: --render, else the config's aamap render with the most rays per
// pixel (the first such: the one worth tuning), else a default.
RenderConfig pickRender(const ExperimentConfig& config, const std::string& name) {
    const RenderConfig* best = nullptr;
    for (const RenderConfig& r : config.renders) {
        if (!name.empty() && r.name == name) return r;
        const StrategyDescriptor* info = findStrategy(r.strategy);
        if (name.empty() && info && info->usesAamap && (!best || r.rpp > best->rpp)) best = &r;
    }
    if (best) return *best;
    if (!name.empty()) {
        std::vector<std::string> names;
        for (const RenderConfig& r : config.renders) names.push_back(r.name);
        throw InputError(config.file.string(), 0, 0,
                         fmt::format("--render '{}' is not a render of this config ({})", name, fmt::join(names, ", ")));
    }
    RenderConfig r;
    r.name = "view";
    r.strategy = kSubsampleStrategyName;
    r.rpp = 16;
    return r;
}

struct Input {
    ViewerSession* session = nullptr;
    ViewMode mode = ViewMode::Aamap;
    double lastX = 0, lastY = 0;
    bool dragging[2] = {false, false};
};

void onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int mods) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    auto& in = *static_cast<Input*>(glfwGetWindowUserPointer(window));
    ViewerSession& s = *in.session;
    ViewerParams p = s.params();
    StrategyParams& sp = p.strategyParams;
    const bool shift = (mods & GLFW_MOD_SHIFT) != 0;
    switch (key) {
        case GLFW_KEY_1: in.mode = ViewMode::Snapshot; break;
        case GLFW_KEY_2: in.mode = ViewMode::Laplacian; break;
        case GLFW_KEY_3: in.mode = ViewMode::Aamap; break;
        case GLFW_KEY_4: in.mode = ViewMode::RaysPerPixel; break;
        case GLFW_KEY_5: in.mode = ViewMode::Render; break;
        case GLFW_KEY_6: in.mode = ViewMode::Error; break;
        case GLFW_KEY_T: s.startTrace(); break;
        case GLFW_KEY_C: s.cancelTrace(); break;
        case GLFW_KEY_R: s.camera().reset(); break;
        case GLFW_KEY_B: p.blurRadius += shift ? -1 : 1; break;
        case GLFW_KEY_F: p.noiseFloor *= shift ? 1.0 / 1.25 : 1.25; break;
        case GLFW_KEY_RIGHT_BRACKET: sp.set(kSubsampleSpacing, sp.integer(kSubsampleSpacing) * 2); break;  // setParams clamps
        case GLFW_KEY_LEFT_BRACKET: sp.set(kSubsampleSpacing, std::max(1, sp.integer(kSubsampleSpacing) / 2)); break;
        case GLFW_KEY_EQUAL: sp.set(kSubsampleThreshold, sp.real(kSubsampleThreshold) + 0.5); break;
        case GLFW_KEY_MINUS: sp.set(kSubsampleThreshold, sp.real(kSubsampleThreshold) - 0.5); break;
        case GLFW_KEY_PERIOD: p.strata += 1; break;
        case GLFW_KEY_COMMA: p.strata -= 1; break;
        case GLFW_KEY_G: p.strategy = nextViewerStrategy(p.strategy); break;
        case GLFW_KEY_H: std::printf("%s\n", viewerControls()); break;
        case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window, GLFW_TRUE); break;
        default: return;
    }
    s.setParams(p);
}

void onMouseButton(GLFWwindow* window, int button, int action, int /*mods*/) {
    auto& in = *static_cast<Input*>(glfwGetWindowUserPointer(window));
    if (button > 1) return;
    in.dragging[button] = action == GLFW_PRESS;
    glfwGetCursorPos(window, &in.lastX, &in.lastY);
}

void onCursor(GLFWwindow* window, double x, double y) {
    auto& in = *static_cast<Input*>(glfwGetWindowUserPointer(window));
    const float dx = static_cast<float>(x - in.lastX) * 0.005f, dy = static_cast<float>(y - in.lastY) * 0.005f;
    in.lastX = x;
    in.lastY = y;
    if (in.dragging[0]) in.session->camera().orbit(-dx, -dy);
    else if (in.dragging[1]) in.session->camera().look(-dx, -dy);
}

void onScroll(GLFWwindow* window, double /*dx*/, double dy) {
    auto& in = *static_cast<Input*>(glfwGetWindowUserPointer(window));
    in.session->camera().dolly(static_cast<float>(dy) * 0.1f);
}

// Held keys move the camera at a rate, so the motion does not depend on the frame rate.
void continuousMotion(GLFWwindow* window, CameraRig& camera, float dt) {
    const auto held = [window](int key) { return glfwGetKey(window, key) == GLFW_PRESS ? 1.0f : 0.0f; };
    const glm::vec3 fly(held(GLFW_KEY_D) - held(GLFW_KEY_A), held(GLFW_KEY_E) - held(GLFW_KEY_Q),
                        held(GLFW_KEY_W) - held(GLFW_KEY_S));
    if (fly != glm::vec3(0.0f)) camera.fly(fly * (0.5f * dt));
    const float yaw = held(GLFW_KEY_LEFT) - held(GLFW_KEY_RIGHT), pitch = held(GLFW_KEY_UP) - held(GLFW_KEY_DOWN);
    if (yaw != 0.0f || pitch != 0.0f) camera.orbit(yaw * dt, pitch * dt);
}

}  // namespace

bool viewerBuilt() { return true; }

void runViewer(const ExperimentConfig& config, const ViewerOptions& options) {
    Input input;
    if (!parse(options.mode, input.mode))
        throw InputError("--mode", 0, 0, fmt::format("unknown view mode '{}'", options.mode));
    const RenderConfig render = pickRender(config, options.render);
    GlfwLibrary glfw;  // first: no display is the most likely problem, say it before loading anything

    PreparedScene prepared = prepareScene(config);
    const int width = prepared.width, height = prepared.height;

    ContextOptions co;
    co.validation = options.validation;
    co.device = options.device;
    std::uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    if (!names) throw EnvironmentError(fmt::format("no Vulkan surface support for windows: {}", gGlfwError));
    co.instanceExtensions.assign(names, names + count);
    co.swapchain = true;
    co.canPresent = [](VkInstance instance, VkPhysicalDevice device, std::uint32_t family) {
        return glfwGetPhysicalDevicePresentationSupport(instance, device, family) == GLFW_TRUE;
    };
    VulkanContext context(co);
    if (options.validation && !context.validationEnabled())
        throw EnvironmentError("validation was requested but VK_LAYER_KHRONOS_validation is not available");
    {
        const int zoom = options.zoom > 0 ? options.zoom : std::max(1, 512 / std::max(width, height));
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        Window window;
        window.handle = glfwCreateWindow(width * zoom, height * zoom, "aamap view", nullptr, nullptr);
        if (!window.handle) throw EnvironmentError(fmt::format("cannot open a window: {}", gGlfwError));
        Presenter presenter(context, window.handle);
        ViewerSession session(context, config, std::move(prepared), render, options.threads);
        input.session = &session;
        glfwSetWindowUserPointer(window.handle, &input);
        glfwSetKeyCallback(window.handle, onKey);
        glfwSetMouseButtonCallback(window.handle, onMouseButton);
        glfwSetCursorPosCallback(window.handle, onCursor);
        glfwSetScrollCallback(window.handle, onScroll);
        spdlog::info("view: {}x{} render, tracing '{}' ({}); press H for the controls", width, height, render.name,
                     render.strategy);

        session.update();
        if (options.trace) session.startTrace();
        std::string title;
        auto last = std::chrono::steady_clock::now();
        for (int frame = 1; !glfwWindowShouldClose(window.handle); ++frame) {
            const bool lastFrame = options.frames > 0 && frame >= options.frames;
            if (session.tracing()) glfwPollEvents();
            else glfwWaitEventsTimeout(1.0 / 30.0);  // idle: no busy loop
            const auto now = std::chrono::steady_clock::now();
            continuousMotion(window.handle, session.camera(), std::chrono::duration<float>(now - last).count());
            last = now;
            session.update();
            std::string why;
            ImageRGB8 image = session.display(input.mode, why);
            if (lastFrame) {  // a scripted run shows the finished state: the trace, then its error
                session.waitForTrace();
                image = session.display(input.mode, why);
                session.waitForTrace();
                image = session.display(input.mode, why);
            }
            const std::string status = session.status(input.mode) + (why.empty() ? "" : " | " + why);
            if (status != title) glfwSetWindowTitle(window.handle, status.c_str());
            title = status;
            const bool shoot = lastFrame && !options.screenshot.empty();
            std::optional<ImageRGB8> shot = presenter.present(image, shoot);
            if (shoot) {
                if (!shot) throw EnvironmentError(fmt::format("no screenshot: nothing shown ({})", why.empty() ? "window minimised" : why));
                writePng(options.screenshot, *shot);
                spdlog::info("view: screenshot {} ({}x{}, {})", options.screenshot.string(), shot->width(),
                             shot->height(), toString(input.mode));
            }
            if (lastFrame) break;
        }
        spdlog::info("view: {}", title);
    }  // session, presenter and window go before the context: their destruction is validated too
    if (context.validationEnabled() && context.validationMessageCount() > 0)
        throw ValidationFailure(
            fmt::format("{} Vulkan validation message(s), logged above", context.validationMessageCount()));
}

}  // namespace aamap
