// PNG output of CPU images (OpenCV's encoder), kept out of the compositor library so that the
// compositor itself needs no OpenCV.
#pragma once

#include <string>

#include "wrsfov/image.h"
#include "layers/status.h"

namespace wrsfov {

/// Writes an RGBA8 image as PNG (alpha dropped). Fails with the path in the message.
Status writePng(const HostImage& image, const std::string& path);

}  // namespace wrsfov
