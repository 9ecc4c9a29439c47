#include "plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <cairo-svg.h>
#include <cairo.h>
#include <fontconfig/fontconfig.h>

#include "cli.hpp"

namespace tricell::cli {

namespace {

bool ends_with(const std::string& text, const std::string& tail) {
    return text.size() >= tail.size() &&
           text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

// Distinct colours for the series (Tableau 10), as r, g, b in [0, 1].
constexpr std::array<std::array<double, 3>, 8> palette = {{
    {0.122, 0.467, 0.706},
    {1.000, 0.498, 0.055},
    {0.173, 0.627, 0.173},
    {0.839, 0.153, 0.157},
    {0.580, 0.404, 0.741},
    {0.549, 0.337, 0.294},
    {0.890, 0.467, 0.761},
    {0.498, 0.498, 0.498},
}};

// A linear map from data to page coordinates along one axis.
struct Axis {
    double low, high; // data range (the outer ticks)
    double from, to;  // page range
    std::vector<double> ticks;
    double operator()(double v) const { return from + (v - low) / (high - low) * (to - from); }
};

Axis make_axis(double low, double high, double from, double to, bool integers) {
    if (!(high > low)) { // one value, or nothing to show: a unit range around it
        low = std::isfinite(low) ? low - 0.5 : 0;
        high = low + 1;
    }
    Axis axis{low, high, from, to, round_ticks(low, high, 6)};
    if (integers) { // bars stand on whole numbers: no tick between two of them
        axis.ticks.erase(std::remove_if(axis.ticks.begin(), axis.ticks.end(),
                                        [](double t) { return t != std::round(t); }),
                         axis.ticks.end());
    } else {
        axis.low = axis.ticks.front();
        axis.high = axis.ticks.back();
    }
    return axis;
}

std::string tick_text(double value, double step) {
    if (std::abs(value) < 1e-9 * step) {
        value = 0; // not "-1.4e-17" for a tick computed as k * step
    }
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

void text_at(cairo_t* cr, const std::string& text, double x, double y, double align_x,
             double align_y) {
    cairo_text_extents_t extents;
    cairo_text_extents(cr, text.c_str(), &extents);
    cairo_move_to(cr, x - align_x * extents.width - extents.x_bearing,
                  y - align_y * extents.height - extents.y_bearing);
    cairo_show_text(cr, text.c_str());
}

void draw(cairo_t* cr, const Plot& plot) {
    const double w = plot.width, h = plot.height;
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);

    // Data ranges (bars: every x is a category position, bars from 0).
    double x_low = INFINITY, x_high = -INFINITY, y_low = 0, y_high = -INFINITY;
    for (const Series& s : plot.series) {
        for (std::size_t k = 0; k < s.x.size(); ++k) {
            if (std::isfinite(s.x[k]) && std::isfinite(s.y[k])) {
                x_low = std::min(x_low, s.x[k]);
                x_high = std::max(x_high, s.x[k]);
                y_low = std::min(y_low, s.y[k]);
                y_high = std::max(y_high, s.y[k]);
            }
        }
    }
    const bool bars = plot.kind == Plot::Kind::bars;
    if (bars && std::isfinite(x_low)) {
        x_low -= 0.5;
        x_high += 0.5;
    }
    const double left = 72, right = w - 20, top = 44, bottom = h - 56;
    const Axis x = make_axis(x_low, x_high, left, right, bars);
    const Axis y = make_axis(y_low, y_high > y_low ? y_high * 1.05 : y_high, bottom, top, false);

    // Grid, ticks and tick labels.
    cairo_set_font_size(cr, 12);
    cairo_set_line_width(cr, 1);
    const double x_step = x.ticks.size() > 1 ? x.ticks[1] - x.ticks[0] : 1;
    for (double t : x.ticks) {
        if (t < x.low || t > x.high) {
            continue;
        }
        cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
        cairo_move_to(cr, x(t), top);
        cairo_line_to(cr, x(t), bottom);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, x(t), bottom);
        cairo_line_to(cr, x(t), bottom + 5);
        cairo_stroke(cr);
        text_at(cr, tick_text(t, x_step), x(t), bottom + 8, 0.5, 0);
    }
    const double y_step = y.ticks.size() > 1 ? y.ticks[1] - y.ticks[0] : 1;
    for (double t : y.ticks) {
        cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
        cairo_move_to(cr, left, y(t));
        cairo_line_to(cr, right, y(t));
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, left - 5, y(t));
        cairo_line_to(cr, left, y(t));
        cairo_stroke(cr);
        text_at(cr, tick_text(t, y_step), left - 8, y(t), 1, 0.5);
    }

    // The series, clipped to the plot area.
    cairo_save(cr);
    cairo_rectangle(cr, left, top, right - left, bottom - top);
    cairo_clip(cr);
    const std::size_t n = plot.series.size();
    for (std::size_t s = 0; s < n; ++s) {
        const Series& series = plot.series[s];
        const auto& colour = palette[s % palette.size()];
        cairo_set_source_rgb(cr, colour[0], colour[1], colour[2]);
        if (bars) {
            const double slot = (x(1) - x(0)) * 0.8 / double(n);
            for (std::size_t k = 0; k < series.x.size(); ++k) {
                if (std::isfinite(series.x[k]) && std::isfinite(series.y[k])) {
                    const double x0 = x(series.x[k]) - 0.4 * (x(1) - x(0)) + double(s) * slot;
                    cairo_rectangle(cr, x0, y(series.y[k]), slot, y(0) - y(series.y[k]));
                }
            }
            cairo_fill(cr);
        } else {
            cairo_set_line_width(cr, 1.5);
            bool pen_down = false;
            for (std::size_t k = 0; k < series.x.size(); ++k) {
                if (!std::isfinite(series.x[k]) || !std::isfinite(series.y[k])) {
                    pen_down = false;
                    continue;
                }
                (pen_down ? cairo_line_to : cairo_move_to)(cr, x(series.x[k]), y(series.y[k]));
                pen_down = true;
            }
            cairo_stroke(cr);
        }
    }
    cairo_restore(cr);

    // Frame, labels and title.
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1);
    cairo_rectangle(cr, left, top, right - left, bottom - top);
    cairo_stroke(cr);
    cairo_set_font_size(cr, 14);
    text_at(cr, plot.x_label, (left + right) / 2, h - 8, 0.5, 1);
    cairo_save(cr);
    cairo_translate(cr, 16, (top + bottom) / 2);
    cairo_rotate(cr, -M_PI / 2);
    text_at(cr, plot.y_label, 0, 0, 0.5, 0.5);
    cairo_restore(cr);
    cairo_set_font_size(cr, 16);
    text_at(cr, plot.title, (left + right) / 2, 12, 0.5, 0);

    // Legend, top right inside the frame, when there is more than one series.
    if (n > 1) {
        cairo_set_font_size(cr, 12);
        double widest = 0;
        for (const Series& s : plot.series) {
            cairo_text_extents_t extents;
            cairo_text_extents(cr, s.label.c_str(), &extents);
            widest = std::max(widest, extents.x_advance);
        }
        const double row = 18, box_w = widest + 40, box_h = row * double(n) + 8;
        const double bx = right - box_w - 8, by = top + 8;
        cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
        cairo_rectangle(cr, bx, by, box_w, box_h);
        cairo_fill_preserve(cr);
        cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
        cairo_stroke(cr);
        for (std::size_t s = 0; s < n; ++s) {
            const auto& colour = palette[s % palette.size()];
            const double cy = by + 4 + row * (double(s) + 0.5);
            cairo_set_source_rgb(cr, colour[0], colour[1], colour[2]);
            if (bars) {
                cairo_rectangle(cr, bx + 8, cy - 5, 20, 10);
                cairo_fill(cr);
            } else {
                cairo_set_line_width(cr, 2);
                cairo_move_to(cr, bx + 8, cy);
                cairo_line_to(cr, bx + 28, cy);
                cairo_stroke(cr);
            }
            cairo_set_source_rgb(cr, 0, 0, 0);
            text_at(cr, plot.series[s].label, bx + 34, cy, 0, 0.5);
        }
    }
}

// cairo and fontconfig keep font caches for the life of the process, which LeakSanitizer reports
// at exit; with no cairo object left, both are emptied (and fill again on the next plot).
void release_font_caches() {
    cairo_debug_reset_static_data();
    FcFini();
}

cairo_status_t write_to_output(void* closure, const unsigned char* data, unsigned int length) {
    static_cast<Output*>(closure)->write(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

void check(cairo_status_t status, const std::string& path) {
    if (status != CAIRO_STATUS_SUCCESS) {
        throw std::runtime_error("cannot draw " + path + " (" + cairo_status_to_string(status) +
                                 ")");
    }
}

} // namespace

bool take_plot(Arguments& arguments, std::string& path) {
    if (!arguments.option("--plot")) {
        return false;
    }
    path = arguments.value();
    if (!ends_with(path, ".svg") && !ends_with(path, ".png")) {
        arguments.fail("--plot: cannot tell the image format of '" + path +
                       "', expected a name ending in .svg or .png");
    }
    return true;
}

void write_plot(const Plot& plot, const std::string& path) {
    Output out(path);
    if (ends_with(path, ".svg")) {
        cairo_surface_t* surface =
            cairo_svg_surface_create_for_stream(write_to_output, &out, plot.width, plot.height);
        cairo_t* cr = cairo_create(surface);
        draw(cr, plot);
        const cairo_status_t status = cairo_status(cr);
        cairo_destroy(cr);
        cairo_surface_finish(surface); // writes the document
        const cairo_status_t finished = cairo_surface_status(surface);
        cairo_surface_destroy(surface);
        release_font_caches();
        check(status, path);
        check(finished, path);
    } else {
        cairo_surface_t* surface =
            cairo_image_surface_create(CAIRO_FORMAT_RGB24, plot.width, plot.height);
        cairo_t* cr = cairo_create(surface);
        draw(cr, plot);
        const cairo_status_t status = cairo_status(cr);
        cairo_destroy(cr);
        const cairo_status_t written =
            status == CAIRO_STATUS_SUCCESS
                ? cairo_surface_write_to_png_stream(surface, write_to_output, &out)
                : status;
        cairo_surface_destroy(surface);
        release_font_caches();
        check(status, path);
        check(written, path);
    }
    out.commit();
}

std::vector<double> round_ticks(double low, double high, int target) {
    const double span = high - low;
    if (!(span > 0) || !std::isfinite(span)) {
        return {low};
    }
    const double raw = span / std::max(1, target);
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    double step = 10 * power;
    for (double m : {1.0, 2.0, 5.0}) {
        if (m * power >= raw) {
            step = m * power;
            break;
        }
    }
    const double first = std::floor(low / step + 1e-9);
    const double last = std::ceil(high / step - 1e-9);
    std::vector<double> ticks;
    for (double k = first; k <= last; ++k) {
        ticks.push_back(k * step);
    }
    return ticks;
}

} // namespace tricell::cli
