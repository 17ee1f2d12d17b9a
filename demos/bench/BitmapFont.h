// A tiny bitmap font of our own for labels on the bench's pictures: 5x7 glyphs (capitals and
// digits 7 rows high, lower case 5, with 2 rows below the baseline for descenders), drawn at an
// integer scale. Covers ASCII letters, digits, space and common punctuation; any other character
// is drawn as '?'.
#pragma once

#include "Raster.h"

#include <climits>
#include <cstdint>
#include <string>

namespace btbench {

constexpr int kGlyphWidth = 5;    // columns of a glyph
constexpr int kGlyphHeight = 9;   // rows: 7 down to the baseline, 2 below it
constexpr int kGlyphAdvance = 6;  // columns from one glyph to the next (one blank between)

// Width and height in pixels of `text` drawn at `scale` (no trailing blank column).
int textWidth(const std::string& text, int scale);
inline int textHeight(int scale) { return kGlyphHeight * scale; }

// Draws `text` with its top-left corner at (x, y), each font pixel a scale x scale square of
// colour `rgb`; only the ink is drawn (the background shows through). Pixels outside the image,
// or outside columns [clipX0, clipX1), are left alone.
void drawText(Image& image, int x, int y, const std::string& text, int scale, const uint8_t rgb[3], int clipX0 = 0,
              int clipX1 = INT_MAX);

}  // namespace btbench
