#include "render/legend.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "render/bitmap_font.h"
#include "render/palette.h"

namespace sculpt::render {

namespace {

// Layout in font pixels (the unit the whole legend scales by).
constexpr int kPadding = 4;
constexpr int kBarWidth = 60, kBarHeight = 6;
constexpr int kTickHeight = 2;
constexpr int kSwatchGap = 5, kSwatchSize = 6, kSwatchLabelGap = 2;
constexpr int kMargin = 4;  // from the view's edges
constexpr std::string_view kTitle = "det J (log scale)";
constexpr std::string_view kFoldLabel = "fold";

class LegendBuilder {
public:
    LegendBuilder(float originX, float originY, float unit) : x0_(originX), y0_(originY), unit_(unit) {}

    // A rectangle in font pixels from the legend's top-left corner; fill and map positions at its left and
    // right edges.
    void rectangle(float x, float y, float w, float h, const Rgba& color, float fill = kFillColor,
                   float mapLeft = 0.0f, float mapRight = 0.0f) {
        const float left = x0_ + x * unit_, top = y0_ + y * unit_, right = left + w * unit_, bottom = top + h * unit_;
        const auto vertex = [&](float px, float py, float map) {
            // note: push_back, not insert of an initializer list, which GCC 12 -O3 misreads as an overflow.
            for (float value : {px, py, color.r, color.g, color.b, color.a, fill, map}) vertices_.push_back(value);
        };
        vertex(left, top, mapLeft);
        vertex(left, bottom, mapLeft);
        vertex(right, top, mapRight);
        vertex(right, top, mapRight);
        vertex(left, bottom, mapLeft);
        vertex(right, bottom, mapRight);
    }

    // Text with its top-left corner at (x, y), one rectangle per run of lit font pixels in a row.
    void text(float x, float y, std::string_view text, const Rgba& color) {
        for (size_t c = 0; c < text.size(); ++c) {
            const auto rows = glyphRows(text[c]);
            for (int row = 0; row < kGlyphHeight; ++row)
                for (int column = 0; column < kGlyphWidth;) {
                    const auto lit = [&](int k) { return k < kGlyphWidth && ((rows[size_t(row)] >> (kGlyphWidth - 1 - k)) & 1); };
                    if (!lit(column)) {
                        ++column;
                        continue;
                    }
                    int end = column;
                    while (lit(end)) ++end;
                    rectangle(x + float(c) * kGlyphAdvance + float(column), y + float(row), float(end - column), 1.0f, color);
                    column = end;
                }
        }
    }

    std::vector<float> take() { return std::move(vertices_); }

private:
    float x0_, y0_, unit_;
    std::vector<float> vertices_;
};

}  // namespace

std::string legendNumber(float value, bool reciprocal) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", double(value));
    return reciprocal ? "1/" + std::string(text) : std::string(text);
}

namespace {

struct LegendLayout {
    float unit;
    int legendWidth, legendHeight, barTop, labelTop;
};

LegendLayout legendLayout(float pixelScale) {
    LegendLayout l{};
    l.unit = std::max(1.0f, std::round(2.0f * pixelScale));
    const int foldWidth = kSwatchGap + kSwatchSize + kSwatchLabelGap + textWidth(kFoldLabel);
    const int contentWidth = std::max(textWidth(kTitle), kBarWidth + foldWidth);
    l.legendWidth = contentWidth + 2 * kPadding;
    l.barTop = kPadding + kGlyphHeight + 3;
    l.labelTop = l.barTop + kBarHeight + kTickHeight + 1;
    l.legendHeight = l.labelTop + kGlyphHeight + kPadding;
    return l;
}

}  // namespace

float jacobianLegendHeight(float pixelScale) {
    const LegendLayout l = legendLayout(pixelScale);
    return static_cast<float>(l.legendHeight + kMargin) * l.unit;
}

std::vector<float> buildJacobianLegend(int width, int height, float pixelScale, float insetBottom, float range) {
    const LegendLayout layout = legendLayout(pixelScale);
    const float unit = layout.unit;
    const int legendWidth = layout.legendWidth, legendHeight = layout.legendHeight;
    const int barTop = layout.barTop, labelTop = layout.labelTop;
    const float left = float(width) - (legendWidth + kMargin) * unit;
    const float top = float(height) - insetBottom - (legendHeight + kMargin) * unit;
    if (left < 0.0f || top < 0.0f) return {};

    LegendBuilder legend(left, top, unit);
    legend.rectangle(0, 0, float(legendWidth), float(legendHeight), kLegendPanelColor);
    legend.text(kPadding, kPadding, kTitle, kLegendTextColor);
    // The bar: the map from -1 (det J = 1 / range) to 1 (range), in the surface shader's own colours.
    legend.rectangle(kPadding, barTop, kBarWidth, kBarHeight, kLegendTextColor, kFillJacobianMap, -1.0f, 1.0f);
    const std::string low = legendNumber(range, true), high = legendNumber(range, false);
    const float ticks[3] = {0.0f, 0.5f * (kBarWidth - 1), float(kBarWidth - 1)};
    for (float tick : ticks) legend.rectangle(kPadding + tick, barTop + kBarHeight, 1, kTickHeight, kLegendTextColor);
    legend.text(kPadding, labelTop, low, kLegendTextColor);
    legend.text(kPadding + ticks[1] - 2.0f, labelTop, "1", kLegendTextColor);
    legend.text(kPadding + kBarWidth - float(textWidth(high)), labelTop, high, kLegendTextColor);
    // Fold-over (det J <= 0): the stripes of the surface.
    const float swatchLeft = kPadding + kBarWidth + kSwatchGap;
    legend.rectangle(swatchLeft, barTop, kSwatchSize, kSwatchSize, kLegendTextColor, kFillFold);
    legend.text(swatchLeft + kSwatchSize + kSwatchLabelGap, barTop - 0.5f, kFoldLabel, kLegendTextColor);
    return legend.take();
}

}  // namespace sculpt::render
