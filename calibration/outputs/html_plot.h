// The pieces of mbx's offline HTML pages (calibration.html,
// excitation.html): escaped text, locale-independent numbers and inline SVG
// line plots with their axes, so every page opens without a network and
// can be mailed as one file.
#pragma once
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mbx::calibration::html_plot {

// ~digits significant digits, locale-independent; "n/a" when not finite.
std::string num(double v, int digits = 4);
// A pixel coordinate to a tenth of a pixel.
void coord(std::string& out, double v);
// Text for HTML content and attribute values: escaped and valid UTF-8.
std::string esc(std::string_view s);
// Tick positions over [lo, hi]: steps of 1, 2 or 5 times a power of ten.
std::vector<double> ticks(double lo, double hi, int target = 5);

struct Series {
    std::string name;
    const char* color;
    const std::vector<double>* x;
    const std::vector<double>* y;
    bool points = false;  // scatter rather than a line
};

struct Plot {
    std::string title, xlabel, ylabel;
    std::vector<Series> series;
};

constexpr double kWidth = 760, kHeight = 310, kLeft = 72, kRight = 16, kTop = 42, kBottom = 44;
// Beyond this many points a series is strided: the page stays small and a
// browser draws it at once.
constexpr size_t kMaxPoints = 4000;

void text(std::string& out, double x, double y, const std::string& s, const char* anchor, const char* extra = "");
void line(std::string& out, double x1, double y1, double x2, double y2);

// The frame, grid and tick labels of a plot over [x0, x1] x [y0, y1].
struct Frame {
    double x0, x1, y0, y1;
    double px(double x) const { return kLeft + (x - x0) / (x1 - x0) * (kWidth - kLeft - kRight); }
    double py(double y) const { return kHeight - kBottom - (y - y0) / (y1 - y0) * (kHeight - kTop - kBottom); }
};
// Opens an <svg> with the frame; `xticks` false leaves the x axis to the
// caller (categories).
void axes(std::string& out, const Frame& f, const std::string& title, const std::string& xlabel,
          const std::string& ylabel, bool xticks);
void legend(std::string& out, const std::vector<std::pair<std::string, const char*>>& items);
// A whole line (or scatter) plot.
std::string svg(const Plot& p);

// The pages' shared style sheet.
extern const char* const kStyle;

}  // namespace mbx::calibration::html_plot
