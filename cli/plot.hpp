// Plots for the command (--plot PATH), drawn with cairo: a line plot (g(r), n(r)) or grouped
// bars (a histogram of coordination numbers per element), with axes, ticks at round numbers
// (1, 2 or 5 times a power of ten), axis labels, a title and a legend when there are several
// series. The extension of PATH picks the image: *.svg (cairo's SVG surface, vector) or *.png
// (an image surface written as PNG). The file is written like --output: through a temporary
// file renamed into place, so PATH is complete or untouched.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace tricell::cli {

class Arguments;

struct Series {
    std::string label;
    std::vector<double> x;
    std::vector<double> y; ///< same size as x; a non-finite y leaves a gap
};

struct Plot {
    enum class Kind { lines, bars };
    Kind kind = Kind::lines;
    std::string title;
    std::string x_label;
    std::string y_label;
    std::vector<Series> series;
    int width = 640; ///< pixels (PNG) or points (SVG)
    int height = 480;
};

/// --plot PATH with PATH ending in .svg or .png (UsageError naming PATH otherwise): consumes it
/// into path and says whether it did.
bool take_plot(Arguments& arguments, std::string& path);

/// Draws `plot` into `path` (.svg or .png), completely or not at all. Throws std::runtime_error
/// when the file cannot be written.
void write_plot(const Plot& plot, const std::string& path);

/// Round tick values covering [low, high]: about `target` steps of 1, 2 or 5 times a power of
/// ten, the first at or below low and the last at or above high.
std::vector<double> round_ticks(double low, double high, int target);

} // namespace tricell::cli
