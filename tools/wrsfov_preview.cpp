// wrsfov-preview: the stereo desktop preview (preview/). Parses the command line and runs it.
#include <cstdio>

#include "preview/options.h"
#include "preview/preview_app.h"
#include "cli/cli.h"

int main(int argc, char** argv) {
    using namespace wrsfov::preview;
    auto options = parseArguments(argc, argv);
    if (!options) {
        wrsfov::cli::printUsageError("wrsfov-preview", options.error().message);
        return options.error().code;
    }
    if (options->help || options->version) {
        std::printf("%s%s", options->text.c_str(), options->version ? "\n" : "");
        return kExitOk;
    }
    return runPreview(*options);
}
