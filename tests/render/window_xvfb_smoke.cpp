// Smoke test of the real window (GLFW + GLX + Dear ImGui's GLFW backend) under a virtual X server: runs
//     SCULPT_WINDOW_FRAMES=90 SCULPT_WINDOW_AUTODRAG=1 SCULPT_WINDOW_SCREENSHOT=OUT.png
//         xvfb-run -a -s "-screen 0 1280x800x24" SCULPT
// (90 frames, a scripted drag on the default mesh, a screenshot of the last frame; glfw_main.cpp) and checks
// the exit code, that the PNG was written at the window's size, and that it is a picture (not one colour).
// Then the idle window (issue: an idle window sleeps): SCULPT_WINDOW_IDLE_SECONDS=2 opens the default mesh, waits
// until it is drawn, measures two seconds with no input and closes; at most a couple of frames may be drawn in
// them (a polling loop draws hundreds). Its CPU share is a speed figure: sculpt_bench window_idle reports it.
//
// Usage: window_xvfb_smoke SCULPT_EXECUTABLE OUT.png
// Exit: 0 passed, 1 failed, 77 skipped (no xvfb-run; ctest's SKIP_RETURN_CODE).
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <sys/wait.h>

#include "io/png_image.h"

namespace {

constexpr int kSkipped = 77;
constexpr int kWidth = 1280, kHeight = 800;  // glfw_main.cpp's window size; Xvfb's content scale is 1

int fail(const std::string& message) {
    std::fprintf(stderr, "window_xvfb_smoke: FAILED: %s\n", message.c_str());
    return 1;
}

// Single quotes for the shell (a path with a quote in it stays one word).
std::string shellQuoted(const std::string& text) {
    std::string quoted = "'";
    for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: window_xvfb_smoke SCULPT_EXECUTABLE OUT.png\n");
        return 1;
    }
    const std::string sculpt = argv[1], png = argv[2];
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
        std::printf("window_xvfb_smoke: SKIPPED: xvfb-run is not installed (apt-get install xvfb xauth)\n");
        return kSkipped;
    }
    std::error_code ignored;
    std::filesystem::create_directories(std::filesystem::path(png).parent_path(), ignored);
    std::filesystem::remove(png, ignored);

    // note: under AddressSanitizer (CI's second pass) the leak check is off for this one process. The real
    // window loads the X11/GLX driver stack, which dlcloses itself at glfwTerminate and leaves ~100 bytes
    // that LeakSanitizer can only attribute to "<unknown module>" (no suppression can name it). The same app
    // code runs leak-checked in the offscreen window tests.
    std::string sanitizer;
    if (const char* asan = std::getenv("ASAN_OPTIONS"))
        sanitizer = "ASAN_OPTIONS=" + shellQuoted(std::string(asan) + ":detect_leaks=0") + " ";
    const std::string command = sanitizer + "SCULPT_WINDOW_FRAMES=90 SCULPT_WINDOW_AUTODRAG=1 SCULPT_WINDOW_SCREENSHOT=" +
                                shellQuoted(png) + " xvfb-run -a -s '-screen 0 1280x800x24' " + shellQuoted(sculpt) +
                                " 2>&1";
    std::printf("window_xvfb_smoke: %s\n", command.c_str());
    std::fflush(stdout);
    const int status = std::system(command.c_str());
    if (status == -1 || !WIFEXITED(status)) return fail("the command did not run to its end");
    if (WEXITSTATUS(status) != 0) return fail("the window exited with code " + std::to_string(WEXITSTATUS(status)));

    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;
    if (sculpt::Status read = sculpt::io::readPng(png, width, height, rgba); !read)
        return fail("no screenshot: " + read.message);
    if (width != kWidth || height != kHeight)
        return fail("screenshot is " + std::to_string(width) + " x " + std::to_string(height) + ", expected " +
                    std::to_string(kWidth) + " x " + std::to_string(kHeight));
    // A real frame has the background gradient, the shaded mesh and the UI's text: thousands of colours.
    // A blank or uniformly cleared one has a handful.
    std::set<std::uint32_t> colours;
    for (size_t p = 0; p + 3 < rgba.size() && colours.size() < 1000; p += 4)
        colours.insert(std::uint32_t(rgba[p]) << 16 | std::uint32_t(rgba[p + 1]) << 8 | rgba[p + 2]);
    if (colours.size() < 64) return fail("screenshot has only " + std::to_string(colours.size()) + " colours");
    std::printf("window_xvfb_smoke: screenshot passed (%s: %d x %d, >= %zu colours)\n", png.c_str(), width, height,
                colours.size());

    const std::string idle = sanitizer + "SCULPT_WINDOW_IDLE_SECONDS=2 xvfb-run -a -s '-screen 0 1280x800x24' " +
                             shellQuoted(sculpt) + " 2>&1";
    std::printf("window_xvfb_smoke: %s\n", idle.c_str());
    std::fflush(stdout);
    FILE* pipe = popen(idle.c_str(), "r");
    if (!pipe) return fail("cannot run the idle window");
    std::string output;
    char buffer[512];
    while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
    const int idleStatus = pclose(pipe);
    std::printf("%s", output.c_str());
    if (idleStatus == -1 || !WIFEXITED(idleStatus) || WEXITSTATUS(idleStatus) != 0)
        return fail("the idle window did not exit cleanly");
    const size_t at = output.find("sculpt: idle ");
    double seconds = 0.0, share = 0.0;
    long frames = -1;
    if (at == std::string::npos ||
        std::sscanf(output.c_str() + at, "sculpt: idle %lf s: %lf%% of one core, %ld frames drawn", &seconds, &share,
                    &frames) != 3)
        return fail("the idle window printed no measurement");
    if (frames > 2) return fail("the idle window drew " + std::to_string(frames) + " frames with no input");
    std::printf("window_xvfb_smoke: passed (idle: %ld frames in %.1f s, %.2f%% of one core)\n", frames, seconds, share);
    return 0;
}
