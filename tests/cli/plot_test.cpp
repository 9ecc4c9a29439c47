// Plots of the command (cli/plot.hpp): each kind is drawn to PNG and SVG and checked to
// be a valid image of the asked size with drawn pixels (PNG read back with cairo) or drawing
// elements (SVG); tick values are round and cover the data.
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "plot.hpp"

namespace {

namespace fs = std::filesystem;
using tricell::cli::Plot;
using tricell::cli::Series;

std::string scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / "tricell-plot-test";
    fs::create_directories(dir);
    return (dir / name).string();
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

Plot line_plot() {
    Plot plot;
    plot.title = "g(r)";
    plot.x_label = "r (Angstrom)";
    plot.y_label = "g(r)";
    for (int s = 0; s < 3; ++s) {
        Series series{"curve " + std::to_string(s), {}, {}};
        for (int k = 0; k < 200; ++k) {
            const double r = 0.05 * (k + 0.5);
            series.x.push_back(r);
            series.y.push_back(1 + std::exp(-(r - 2 - s) * (r - 2 - s) * 4) * (3 - s));
        }
        series.y[50] = NAN; // a gap
        plot.series.push_back(series);
    }
    return plot;
}

Plot bar_plot() {
    Plot plot;
    plot.kind = Plot::Kind::bars;
    plot.title = "Coordination numbers";
    plot.x_label = "coordination number";
    plot.y_label = "atoms";
    plot.series = {Series{"Si", {4}, {3}}, Series{"O", {1, 2}, {1, 5}}};
    plot.width = 500;
    plot.height = 300;
    return plot;
}

// Pixels that are not the white background, and pixels of the first series' colour.
struct Pixels {
    int width = 0, height = 0;
    std::size_t drawn = 0;
    std::size_t first_colour = 0;
};

Pixels read_png(const std::string& path) {
    cairo_surface_t* image = cairo_image_surface_create_from_png(path.c_str());
    Pixels p;
    if (cairo_surface_status(image) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(image);
        return p;
    }
    p.width = cairo_image_surface_get_width(image);
    p.height = cairo_image_surface_get_height(image);
    const int stride = cairo_image_surface_get_stride(image);
    const unsigned char* data = cairo_image_surface_get_data(image);
    for (int y = 0; y < p.height; ++y) {
        const auto* row = reinterpret_cast<const std::uint32_t*>(data + y * stride);
        for (int x = 0; x < p.width; ++x) {
            const std::uint32_t rgb = row[x] & 0xFFFFFF;
            p.drawn += rgb != 0xFFFFFF;
            const int r = int(rgb >> 16), g = int((rgb >> 8) & 0xFF), b = int(rgb & 0xFF);
            // Palette colour 0 is (31, 119, 180).
            p.first_colour +=
                std::abs(r - 31) < 8 && std::abs(g - 119) < 8 && std::abs(b - 180) < 8;
        }
    }
    cairo_surface_destroy(image);
    return p;
}

TEST(Plot, PngOfEachKindHasTheSizeAndDrawnPixels) {
    for (const Plot& plot : {line_plot(), bar_plot()}) {
        SCOPED_TRACE(plot.title);
        const std::string path = scratch(plot.title == "g(r)" ? "lines.png" : "bars.png");
        tricell::cli::write_plot(plot, path);
        const Pixels p = read_png(path);
        EXPECT_EQ(p.width, plot.width);
        EXPECT_EQ(p.height, plot.height);
        const std::size_t all = std::size_t(plot.width) * std::size_t(plot.height);
        EXPECT_GT(p.drawn, all / 50);    // axes, text and data
        EXPECT_LT(p.drawn, all / 2);     // but mostly background
        EXPECT_GT(p.first_colour, 100u); // the first series is there
    }
}

TEST(Plot, SvgOfEachKindHasTheSizeAndDrawingElements) {
    for (const Plot& plot : {line_plot(), bar_plot()}) {
        SCOPED_TRACE(plot.title);
        const std::string path = scratch(plot.title == "g(r)" ? "lines.svg" : "bars.svg");
        tricell::cli::write_plot(plot, path);
        const std::string svg = slurp(path);
        ASSERT_EQ(svg.rfind("<?xml", 0), 0u);
        const std::size_t open = svg.find("<svg");
        ASSERT_NE(open, std::string::npos);
        const std::string tag = svg.substr(open, svg.find('>', open) - open);
        EXPECT_NE(tag.find("width=\"" + std::to_string(plot.width) + "pt\""), std::string::npos)
            << tag;
        EXPECT_NE(tag.find("height=\"" + std::to_string(plot.height) + "pt\""), std::string::npos)
            << tag;
        std::size_t paths = 0;
        for (std::size_t at = svg.find("<path"); at != std::string::npos;
             at = svg.find("<path", at + 1)) {
            ++paths;
        }
        EXPECT_GT(paths, 10u);
        // The first series' colour (31, 119, 180) is used.
        EXPECT_NE(svg.find("rgb(12.2"), std::string::npos);
        EXPECT_EQ(svg.substr(svg.find_last_not_of("\n") - 5, 6), "</svg>");
    }
}

TEST(Plot, AnUnwritablePathFailsAndLeavesNothing) {
    const std::string path = scratch("no/such/dir/plot.png");
    EXPECT_THROW(tricell::cli::write_plot(line_plot(), path), std::runtime_error);
    EXPECT_FALSE(fs::exists(fs::path(path).parent_path()));
}

TEST(Plot, EmptyAndFlatDataStillDraw) {
    Plot plot = line_plot();
    plot.series = {Series{"flat", {1, 2, 3}, {2, 2, 2}}};
    const std::string path = scratch("flat.png");
    tricell::cli::write_plot(plot, path);
    EXPECT_EQ(read_png(path).width, plot.width);
    plot.series.clear();
    tricell::cli::write_plot(plot, path);
    EXPECT_GT(read_png(path).drawn, 0u);
}

TEST(Plot, TicksAreRoundAndCoverTheRange) {
    std::mt19937_64 random(5);
    std::uniform_real_distribution<double> exponent(-6, 6), unit(0, 1);
    for (int k = 0; k < 2000; ++k) {
        SCOPED_TRACE(k);
        const double scale = std::pow(10.0, exponent(random));
        const double a = (unit(random) - 0.3) * scale, b = a + unit(random) * scale + 1e-3 * scale;
        const std::vector<double> t = tricell::cli::round_ticks(a, b, 6);
        ASSERT_GE(t.size(), 2u);
        EXPECT_LE(t.size(), 14u);
        EXPECT_LE(t.front(), a);
        EXPECT_GE(t.back(), b);
        const double step = t[1] - t[0];
        const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
        EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 ||
                    std::abs(mantissa - 5) < 1e-6)
            << step;
        for (double v : t) {
            EXPECT_NEAR(v / step, std::round(v / step), 1e-6);
        }
    }
}

} // namespace
