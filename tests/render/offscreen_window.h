// A window for SculptApp without a display: an EGL context, a Dear ImGui context set up as the GLFW window
// sets it up (the app's theme and font, no imgui.ini, fixed io.DeltaTime) and a render target the frames go
// to. Shared by the UI golden tests (window_golden_test.cpp) and the window benchmarks (sculpt_bench).
//
// note: EGL, not OSMesa, because Dear ImGui's prebuilt OpenGL3 backend loads GL through libGL/GLVND, which
// reaches EGL contexts but not OSMesa ones (window_app_test.cpp says more). open() fails with EGL's message
// where EGL is missing; callers skip then.
//
// Plain Status results, no Catch2: the benchmark uses it too.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include <imgui.h>

#include "app/window/sculpt_app.h"
#include "app/window/ui_style.h"
#include "core/status.h"
#include "render/gl_functions.h"
#include "render/offscreen_context.h"
#include "render/render_target.h"

namespace sculpt::test {

class OffscreenWindow {
public:
    OffscreenWindow() = default;
    ~OffscreenWindow() { close(); }
    OffscreenWindow(const OffscreenWindow&) = delete;
    OffscreenWindow& operator=(const OffscreenWindow&) = delete;

    // Creates the EGL context and a fresh ImGui context, initialises app's graphics (renderer + ImGui
    // backend) and a width x height target with `samples` MSAA samples (<= 1: none, as the window on a
    // software rasterizer). app must outlive the window (or close() be called first).
    Status open(app::SculptApp& app, int width, int height, int samples) {
        close();
        if (Status s = render::OffscreenContext::create(render::GlBackend::Egl, context_); !s) return s;
        app::createUiContext(1.0f);
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;  // fresh state for every window: nothing read or written
        io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
        io.DisplayFramebufferScale = ImVec2(1.0f, 1.0f);
        io.DeltaTime = 1.0f / 60.0f;  // fixed: ImGui's animations and frame-rate estimate repeat exactly
        app_ = &app;
        if (Status s = app.initGraphics(context_->getProcAddress()); !s) {
            close();
            return s;
        }
        app.renderer().setPixelScale(1.0f);
        target_ = std::make_unique<render::RenderTarget>(context_->gl());
        if (Status s = target_->resize(width, height, samples); !s) {
            close();
            return s;
        }
        width_ = width;
        height_ = height;
        return Status::success();
    }

    // One full frame (scene + UI) into the target; waits until the GL finished it. image: read back (top-down).
    Status frame(render::Rgba8Image* image = nullptr) {
        if (Status s = renderOnly(); !s) return s;
        if (image) return target_->read(*image);
        context_->gl().Finish();
        return Status::success();
    }

    // Records the frame's GL commands without waiting for them (finish() or frame() waits).
    Status renderOnly() {
        if (!context_) return Status::error("offscreen window not open");
        if (Status s = context_->makeCurrent(); !s) return s;
        target_->bind();
        return app_->renderFrame(width_, height_);
    }
    void finish() { context_->gl().Finish(); }

    // One byte per pixel (rows top-down), 1 where a window of the last frame's UI is drawn: the bounding box
    // of each ImGui draw list's vertices (one list per window, the window background included).
    std::vector<std::uint8_t> uiMask() const {
        std::vector<std::uint8_t> mask(static_cast<size_t>(width_) * static_cast<size_t>(height_), 0);
        const ImDrawData* data = ImGui::GetDrawData();
        if (!data) return mask;
        for (int l = 0; l < data->CmdListsCount; ++l) {
            const ImDrawList* list = data->CmdLists[l];
            if (list->VtxBuffer.Size == 0) continue;
            ImVec2 lo = list->VtxBuffer[0].pos, hi = lo;
            for (const ImDrawVert& v : list->VtxBuffer) {
                lo = ImVec2(std::min(lo.x, v.pos.x), std::min(lo.y, v.pos.y));
                hi = ImVec2(std::max(hi.x, v.pos.x), std::max(hi.y, v.pos.y));
            }
            const int x0 = std::max(0, static_cast<int>(lo.x) - 1), y0 = std::max(0, static_cast<int>(lo.y) - 1);
            const int x1 = std::min(width_, static_cast<int>(hi.x) + 2), y1 = std::min(height_, static_cast<int>(hi.y) + 2);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) mask[static_cast<size_t>(y) * static_cast<size_t>(width_) + x] = 1;
        }
        return mask;
    }

    const render::OffscreenContext& context() const { return *context_; }
    bool isOpen() const { return context_ != nullptr; }

    // Frees the GL objects and both contexts. Safe to call twice.
    void close() {
        if (!context_) return;
        context_->makeCurrent();
        if (target_) target_->release();
        target_.reset();
        if (app_) app_->releaseGraphics();
        app_ = nullptr;
        app::destroyUiContext();
        context_.reset();
    }

private:
    std::unique_ptr<render::OffscreenContext> context_;
    std::unique_ptr<render::RenderTarget> target_;
    app::SculptApp* app_ = nullptr;
    int width_ = 0, height_ = 0;
};

}  // namespace sculpt::test
