#include "PngFile.h"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace btbench {

namespace {

// libpng reports errors by longjmp; keep the message for the exception thrown afterwards.
struct PngError {
    char message[256];
};

void recordPngError(png_structp png, png_const_charp message) {
    auto* error = static_cast<PngError*>(png_get_error_ptr(png));
    std::snprintf(error->message, sizeof error->message, "%s", message);
    png_longjmp(png, 1);
}
void ignorePngWarning(png_structp, png_const_charp) {}

// Only plain C data lives in this frame, so the longjmp from libpng skips no destructor.
bool writeImage(png_structp png, png_infop info, FILE* file, const Image* image) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_init_io(png, file);
    png_set_IHDR(png, info, png_uint_32(image->width), png_uint_32(image->height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < image->height; ++y)
        png_write_row(png, const_cast<png_bytep>(&image->rgb[size_t(y) * size_t(image->width) * 3]));
    png_write_end(png, nullptr);
    return true;
}

}  // namespace

void writePng(const std::string& path, const Image& image) {
    FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) throw std::runtime_error("cannot open " + path + " for writing: " + std::strerror(errno));
    PngError error{};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, &recordPngError, &ignorePngWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    const bool ok = png && info && writeImage(png, info, file, &image);
    png_destroy_write_struct(png ? &png : nullptr, info ? &info : nullptr);
    const bool closed = std::fclose(file) == 0;
    if (!ok) throw std::runtime_error("writing " + path + ": libpng: " + (error.message[0] ? error.message : "out of memory"));
    if (!closed) throw std::runtime_error("writing " + path + ": " + std::strerror(errno));
}

}  // namespace btbench
