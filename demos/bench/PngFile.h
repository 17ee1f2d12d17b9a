// Writes an RGB image as a PNG file with libpng.
#pragma once

#include "Raster.h"

#include <string>

namespace btbench {

// Throws std::runtime_error naming the file when it cannot be written.
void writePng(const std::string& path, const Image& image);

}  // namespace btbench
