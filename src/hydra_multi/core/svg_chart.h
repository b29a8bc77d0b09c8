#pragma once
// Small pieces every chart the project writes shares (trials' bars and scatter plots, the
// station's bandwidth): the colours, number and text formatting, the chart's opening, and axis
// bounds. Plain SVG 1.1 text, no library.

#include <string>

namespace hydra_multi::svg {

/// One colour per series, in order (cycled after 16).
const char* colour(size_t series);
/// `v` with `decimals` digits after the point.
std::string fixed(double v, int decimals);
/// Text with <, > and & escaped for SVG.
std::string escape(const std::string& text);
/// The opening of a chart: the svg element, a white background and the title.
std::string header(double width, double height, const std::string& title);
/// A "nice" upper bound for an axis: 1, 2 or 5 times a power of ten at or above v (1 for v <= 0).
double niceCeiling(double v);

}  // namespace hydra_multi::svg
