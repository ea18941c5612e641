// wrsfov-preview: the stereo desktop preview (preview/). Parses the command line and runs it.
#include <cstdio>

#include "preview/options.h"
#include "preview/preview_app.h"

int main(int argc, char** argv) {
    using namespace wrsfov::preview;
    auto options = parseArguments(argc, argv);
    if (!options) {
        std::fprintf(stderr, "wrsfov-preview: %s\n", options.error().message.c_str());
        std::fprintf(stderr, "%s", usage().c_str());
        return kExitBadArguments;
    }
    if (options->help) {
        std::printf("%s\n%s", usage().c_str(), keyHelp().c_str());
        return kExitOk;
    }
    return runPreview(*options);
}
