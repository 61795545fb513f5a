#include "calibration/outputs/html_plot.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "core/report/utf8.h"

namespace mbx::calibration::html_plot {

// ~4 significant digits, locale-independent (a host may have set a locale
// with decimal commas).
std::string num(double v, int digits) {
    if (!std::isfinite(v)) return "n/a";
    if (v == 0) return "0";
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, digits);
    return std::string(buf, r.ptr);
}

// A pixel coordinate: a tenth of a pixel is finer than any screen.
void coord(std::string& out, double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, std::round(v * 10) / 10, std::chars_format::fixed, 1);
    out.append(buf, r.ptr);
}

// Text for HTML content and attribute values: escaped and valid UTF-8.
std::string esc(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (size_t i = 0; i < s.size();) {
        const char c = s[i];
        if (c == '&') out += "&amp;";
        else if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '"') out += "&quot;";
        else if (c == '\'') out += "&#39;";
        if (c == '&' || c == '<' || c == '>' || c == '"' || c == '\'') {
            ++i;
            continue;
        }
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') {
            out += ' ';
            ++i;
            continue;
        }
        i += append_utf8_or_replacement(out, s, i);
    }
    return out;
}

// Tick positions over [lo, hi]: steps of 1, 2 or 5 times a power of ten,
// about `target` of them.
std::vector<double> ticks(double lo, double hi, int target) {
    std::vector<double> out;
    const double span = hi - lo;
    if (!(span > 0) || !std::isfinite(span)) return {lo};
    const double raw = span / target, mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double frac = raw / mag;
    const double step = (frac < 1.5 ? 1 : frac < 3.5 ? 2 : frac < 7.5 ? 5 : 10) * mag;
    // Counted in whole steps (t += step could stall where step is below the
    // spacing of doubles near lo), and never more than a few dozen.
    const double first = std::ceil(lo / step - 1e-9);
    for (int k = 0; k < 50; ++k) {
        const double t = (first + k) * step;
        if (t > hi + step * 1e-9) break;
        out.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
    }
    return out;
}




static void range_of(const std::vector<Series>& series, bool x, double& lo, double& hi) {
    lo = INFINITY, hi = -INFINITY;
    for (const Series& s : series)
        for (double v : x ? *s.x : *s.y)
            if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (!(lo <= hi)) lo = 0, hi = 1;
    if (hi - lo <= 1e-12 * std::max(std::abs(lo), std::abs(hi))) {
        const double pad = lo == 0 ? 1 : std::abs(lo) * 0.1;
        lo -= pad, hi += pad;
    } else if (!x) {
        const double pad = 0.04 * (hi - lo);
        lo -= pad, hi += pad;
    }
}

void text(std::string& out, double x, double y, const std::string& s, const char* anchor, const char* extra) {
    out += "<text x=\"";
    coord(out, x);
    out += "\" y=\"";
    coord(out, y);
    out += "\" text-anchor=\"";
    out += anchor;
    out += "\"";
    out += extra;
    out += ">" + esc(s) + "</text>";
}

void line(std::string& out, double x1, double y1, double x2, double y2) {
    out += "<line x1=\"";
    coord(out, x1);
    out += "\" y1=\"";
    coord(out, y1);
    out += "\" x2=\"";
    coord(out, x2);
    out += "\" y2=\"";
    coord(out, y2);
    out += "\"/>";
}


void axes(std::string& out, const Frame& f, const std::string& title, const std::string& xlabel,
          const std::string& ylabel, bool xticks) {
    out += "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " + num(kWidth) + " " + num(kHeight) +
           "\" width=\"" + num(kWidth) + "\" height=\"" + num(kHeight) +
           "\" role=\"img\" font-family=\"sans-serif\" font-size=\"11\"><title>" + esc(title) + "</title>";
    text(out, kLeft, 15, title, "start", " font-weight=\"bold\"");
    // Styles as attributes, not CSS: a plot copied out of the page still draws.
    out += "<g stroke=\"#e4e4e4\">";
    for (double t : ticks(f.y0, f.y1)) line(out, kLeft, f.py(t), kWidth - kRight, f.py(t));
    if (xticks)
        for (double t : ticks(f.x0, f.x1, 8)) line(out, f.px(t), kTop, f.px(t), kHeight - kBottom);
    out += "</g>";
    for (double t : ticks(f.y0, f.y1)) text(out, kLeft - 5, f.py(t) + 4, num(t), "end");
    if (xticks)
        for (double t : ticks(f.x0, f.x1, 8)) text(out, f.px(t), kHeight - kBottom + 15, num(t), "middle");
    out += "<rect fill=\"none\" stroke=\"#888\" x=\"" + num(kLeft) + "\" y=\"" + num(kTop) + "\" width=\"" + num(kWidth - kLeft - kRight) +
           "\" height=\"" + num(kHeight - kTop - kBottom) + "\"/>";
    text(out, (kLeft + kWidth - kRight) / 2, kHeight - 6, xlabel, "middle");
    std::string rotate = " transform=\"rotate(-90 14 " + num((kTop + kHeight - kBottom) / 2) + ")\"";
    text(out, 14, (kTop + kHeight - kBottom) / 2, ylabel, "middle", rotate.c_str());
}

void legend(std::string& out, const std::vector<std::pair<std::string, const char*>>& items) {
    double x = kWidth - kRight;
    for (size_t i = items.size(); i-- > 0;) {
        const double w = 6.5 * double(items[i].first.size()) + 30;
        x -= w;
        out += "<rect x=\"" + num(x) + "\" y=\"22\" width=\"12\" height=\"10\" fill=\"" + items[i].second + "\"/>";
        text(out, x + 16, 31, items[i].first, "start");
    }
}

std::string svg(const Plot& p) {
    Frame f{};
    range_of(p.series, true, f.x0, f.x1);
    range_of(p.series, false, f.y0, f.y1);
    std::string out;
    axes(out, f, p.title, p.xlabel, p.ylabel, true);
    std::vector<std::pair<std::string, const char*>> items;
    for (const Series& s : p.series) {
        items.emplace_back(s.name, s.color);
        const size_t n = std::min(s.x->size(), s.y->size());
        const size_t stride = n > kMaxPoints ? (n + kMaxPoints - 1) / kMaxPoints : 1;
        // Points are zero-length segments with round caps: a dot each, in a
        // fraction of the bytes of a circle element.
        out += s.points ? "<path fill=\"none\" stroke-width=\"3\" stroke-linecap=\"round\" stroke-opacity=\"0.6\" stroke=\""
                        : "<path fill=\"none\" stroke-width=\"1.2\" stroke-linejoin=\"round\" stroke=\"";
        out += s.color;
        out += "\" d=\"";
        bool pen = false;
        for (size_t i = 0; i < n; i += stride) {
            const double x = (*s.x)[i], y = (*s.y)[i];
            if (!std::isfinite(x) || !std::isfinite(y)) {
                pen = false;
                continue;
            }
            if (s.points || !pen) out += 'M';
            else out += ' ';
            coord(out, f.px(x));
            out += ' ';
            coord(out, f.py(y));
            if (s.points) out += "h0";
            pen = true;
        }
        out += "\"/>";
    }
    legend(out, items);
    out += "</svg>\n";
    return out;
}


const char* const kStyle = R"(body{font:14px/1.45 system-ui,sans-serif;margin:1.5em auto;max-width:1100px;padding:0 1em;color:#222}
h1{font-size:1.5em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 7px;text-align:left;vertical-align:top}
td.n{text-align:right;font-variant-numeric:tabular-nums}svg{display:block;margin:.6em 0;max-width:100%;height:auto}
.w{color:#a33}
)";

}  // namespace mbx::calibration::html_plot
