// A tiny 5 x 7 pixel font for the few labels the renderer draws itself (the det J legend's numbers), so
// that headless screenshots carry them without a font file, a font library or Dear ImGui.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace sculpt::render {

inline constexpr int kGlyphWidth = 5;    // font pixels
inline constexpr int kGlyphHeight = 7;   // font pixels
inline constexpr int kGlyphAdvance = 6;  // font pixels from one character to the next

// The glyph of c: kGlyphHeight rows, top first, bit 4 the leftmost column. The font has the digits, space,
// . / ( ) < > = - and the letters of "det J (log scale)" and "fold"; any other character gives a hollow box.
std::array<std::uint8_t, kGlyphHeight> glyphRows(char c);

// Width of `text` in font pixels (kGlyphAdvance per character, no trailing space).
int textWidth(std::string_view text);

}  // namespace sculpt::render
