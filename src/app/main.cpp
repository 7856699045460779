// sculpt: the DMFFD Sculpt executable. `--headless` runs a script without a display; otherwise the window.
#include <cstdlib>
#include <exception>
#include <iostream>

#include "app/cli_options.h"
#include "app/headless.h"
#ifdef SCULPT_HAVE_WINDOW
#include "app/window/glfw_main.h"
#endif

int main(int argc, char** argv) {
    try {
        sculpt::app::CliOptions options;
        if (sculpt::Status s = sculpt::app::parseCommandLine(argc, argv, options); !s) {
            std::cerr << "sculpt: " << s.message << "\n" << sculpt::app::usageText();
            return sculpt::app::kExitBadInput;
        }
        if (options.help) {
            std::cout << sculpt::app::usageText();
            return sculpt::app::kExitOk;
        }
        if (options.headless) return sculpt::app::runHeadless(options, argv[0]);
#ifdef SCULPT_HAVE_WINDOW
        // note: the window shares the cores with the GL driver (llvmpipe renders on the CPU): OpenMP threads
        // that spin while waiting for work steal its time (a 1M-vertex drag step took 3-8 ms instead of 1.5
        // under load). Set before the first parallel region; a user's own setting wins.
        setenv("OMP_WAIT_POLICY", "passive", 0);
        return sculpt::app::runWindow(options.input.empty() ? sculpt::app::defaultMeshPath(argv[0]) : options.input);
#else
        std::cerr << "sculpt: built without the window (SCULPT_BUILD_GL=OFF); run a script with --headless.\n"
                  << sculpt::app::usageText();
        return sculpt::app::kExitBadInput;
#endif
    } catch (const std::exception& e) {
        std::cerr << "sculpt: internal error: " << e.what() << "\n";
        return sculpt::app::kExitInternal;
    }
}
