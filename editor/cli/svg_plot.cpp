#include "cli/svg_plot.h"

#include "cli/common.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace plimsoll::cli {

namespace {

constexpr double kWidth = 960, kHeight = 620;
constexpr double kLeft = 90, kTop = 50, kRight = kWidth - 280, kBottom = kHeight - 70;

// Tableau 10: distinguishable in colour and in grey print.
constexpr std::array<const char*, 10> kColours = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2",
                                                  "#59a14f", "#edc948", "#b07aa1", "#ff9da7",
                                                  "#9c755f", "#bab0ac"};

std::string num(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.1f", v);
    return buffer;
}

bool plottable(double x, double y) {
    return x > 0 && y > 0 && std::isfinite(x) && std::isfinite(y);
}

/// Whole decades [lo, hi] (exponents) around the values; one decade when there is nothing.
struct DecadeRange {
    int lo = 0, hi = 1;

    void widen(double value, bool& any) {
        const int below = static_cast<int>(std::floor(std::log10(value)));
        const int above = static_cast<int>(std::ceil(std::log10(value)));
        lo = any ? std::min(lo, below) : below;
        hi = any ? std::max(hi, above) : above;
        any = true;
    }
    void finish() {
        if (hi <= lo) hi = lo + 1;
    }
    double fraction(double value) const { return (std::log10(value) - lo) / (hi - lo); }
};

std::string decadeLabel(int exponent) {
    return "10<tspan dy=\"-7\" font-size=\"10\">" + std::to_string(exponent) + "</tspan>";
}

/// The document's opening, white background and title.
void openDocument(std::ostream& out, const std::string& title) {
    out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\""
        << kHeight << "\" viewBox=\"0 0 " << kWidth << ' ' << kHeight
        << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
        << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
        << "<text x=\"" << num((kLeft + kRight) / 2) << "\" y=\"28\" text-anchor=\"middle\" "
        << "font-size=\"15\">" << xmlEscaped(title) << "</text>\n";
}

/// The plot area's frame and the axis labels.
void drawFrame(std::ostream& out, const std::string& xLabel, const std::string& yLabel) {
    out << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << kRight - kLeft
        << "\" height=\"" << kBottom - kTop << "\" fill=\"none\" stroke=\"#333\"/>\n"
        << "<text x=\"" << num((kLeft + kRight) / 2) << "\" y=\"" << kHeight - 22
        << "\" text-anchor=\"middle\">" << xmlEscaped(xLabel) << "</text>\n"
        << "<text transform=\"translate(24 " << num((kTop + kBottom) / 2)
        << ") rotate(-90)\" text-anchor=\"middle\">" << xmlEscaped(yLabel) << "</text>\n";
}

/// A dashed vertical line at pixel column x, labelled along it.
void drawMarker(std::ostream& out, double x, const std::string& label) {
    out << "<line x1=\"" << num(x) << "\" y1=\"" << kTop << "\" x2=\"" << num(x) << "\" y2=\""
        << kBottom << "\" stroke=\"#555\" stroke-dasharray=\"6 4\"/>\n"
        << "<text transform=\"translate(" << num(x - 4) << ' ' << kTop + 6
        << ") rotate(-90)\" text-anchor=\"end\" font-size=\"11\" fill=\"#555\">"
        << xmlEscaped(label) << "</text>\n";
}

/// A series' legend line at height y, in the colour of the enclosing group.
void drawLegendEntry(std::ostream& out, double y, const std::string& name) {
    out << "<line x1=\"" << kRight + 16 << "\" y1=\"" << y << "\" x2=\"" << kRight + 40
        << "\" y2=\"" << y << "\" stroke-width=\"2\"/>\n"
        << "<text x=\"" << kRight + 46 << "\" y=\"" << y + 4 << "\" stroke=\"none\" "
        << "fill=\"#222\">" << xmlEscaped(name) << "</text>\n";
}

/// Opens a series' group in its colour and draws its line through the points `keep` accepts
/// (px, py: data to pixels). The caller adds its marks and the legend entry, then closes </g>.
template <class Px, class Py, class Keep>
void openSeries(std::ostream& out, const PlotSeries& s, const char* colour, Px px, Py py,
                Keep keep) {
    std::string path;
    for (const PlotPoint& p : s.points) {
        if (keep(p)) path += (path.empty() ? "" : " ") + num(px(p.x)) + "," + num(py(p.y));
    }
    out << "<g stroke=\"" << colour << "\" fill=\"" << colour << "\">\n"
        << "<polyline points=\"" << path << "\" fill=\"none\" stroke-width=\"1.8\"/>\n";
}

}  // namespace

bool writeSvg(const LogLogPlot& plot, std::ostream& out) {
    DecadeRange xs, ys;
    bool anyX = false, anyY = false;
    for (const PlotSeries& s : plot.series) {
        for (const PlotPoint& p : s.points) {
            if (!plottable(p.x, p.y)) continue;
            xs.widen(p.x, anyX);
            ys.widen(p.y, anyY);
        }
    }
    for (const PlotMarker& m : plot.markers)
        if (plottable(m.x, 1.0)) xs.widen(m.x, anyX);
    xs.finish();
    ys.finish();
    auto px = [&](double x) { return kLeft + xs.fraction(x) * (kRight - kLeft); };
    auto py = [&](double y) { return kBottom - ys.fraction(y) * (kBottom - kTop); };

    openDocument(out, plot.title);

    // Grid: a solid line per decade, faint lines at 2..9 times it.
    out << "<g stroke-width=\"1\">\n";
    for (int e = xs.lo; e <= xs.hi; ++e) {
        for (int k = 1; k <= (e < xs.hi ? 9 : 1); ++k) {
            const double x = px(k * std::pow(10.0, e));
            out << "<line x1=\"" << num(x) << "\" y1=\"" << kTop << "\" x2=\"" << num(x)
                << "\" y2=\"" << kBottom << "\" stroke=\"" << (k == 1 ? "#bbb" : "#eee")
                << "\"/>\n";
        }
        out << "<text x=\"" << num(px(std::pow(10.0, e))) << "\" y=\"" << kBottom + 20
            << "\" text-anchor=\"middle\" stroke=\"none\">" << decadeLabel(e) << "</text>\n";
    }
    for (int e = ys.lo; e <= ys.hi; ++e) {
        for (int k = 1; k <= (e < ys.hi ? 9 : 1); ++k) {
            const double y = py(k * std::pow(10.0, e));
            out << "<line x1=\"" << kLeft << "\" y1=\"" << num(y) << "\" x2=\"" << kRight
                << "\" y2=\"" << num(y) << "\" stroke=\"" << (k == 1 ? "#bbb" : "#eee") << "\"/>\n";
        }
        out << "<text x=\"" << kLeft - 8 << "\" y=\"" << num(py(std::pow(10.0, e)) + 4)
            << "\" text-anchor=\"end\" stroke=\"none\">" << decadeLabel(e) << "</text>\n";
    }
    out << "</g>\n";
    drawFrame(out, plot.xLabel, plot.yLabel);

    for (const PlotMarker& m : plot.markers)
        if (plottable(m.x, 1.0)) drawMarker(out, px(m.x), m.label);

    double legendY = kTop + 10;
    for (std::size_t i = 0; i < plot.series.size(); ++i) {
        const PlotSeries& s = plot.series[i];
        const char* colour = kColours[i % kColours.size()];
        openSeries(out, s, colour, px, py, [](const PlotPoint& p) { return plottable(p.x, p.y); });
        for (const PlotPoint& p : s.points) {
            if (!plottable(p.x, p.y)) continue;
            out << "<circle cx=\"" << num(px(p.x)) << "\" cy=\"" << num(py(p.y))
                << "\" r=\"3.5\"/>\n"
                << "<text x=\"" << num(px(p.x) + 5) << "\" y=\"" << num(py(p.y) - 5)
                << "\" stroke=\"none\" font-size=\"10\">" << xmlEscaped(p.label) << "</text>\n";
        }
        drawLegendEntry(out, legendY, s.name);
        out << "</g>\n";
        legendY += 20;
    }
    out << "</svg>\n";
    return static_cast<bool>(out);
}

}  // namespace plimsoll::cli

namespace plimsoll::cli {

namespace {

/// [lo, hi] widened to whole multiples of a round step (1, 2 or 5 times a power of ten) that
/// gives about eight grid lines.
struct LinearRange {
    double lo = 0, hi = 0, step = 1;
    bool any = false;

    void widen(double value) {
        lo = any ? std::min(lo, value) : value;
        hi = any ? std::max(hi, value) : value;
        any = true;
    }
    void finish() {
        if (!(hi > lo)) lo -= 0.5, hi += 0.5;
        const double raw = (hi - lo) / 8;
        const double decade = std::pow(10.0, std::floor(std::log10(raw)));
        step = raw <= decade       ? decade
               : raw <= 2 * decade ? 2 * decade
               : raw <= 5 * decade ? 5 * decade
                                   : 10 * decade;
        lo = std::floor(lo / step) * step;
        hi = std::ceil(hi / step) * step;
    }
    double fraction(double value) const { return (value - lo) / (hi - lo); }
};

std::string tickLabel(double v, double step) {
    char buffer[32];
    const int decimals = std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9)));
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, std::abs(v) < 1e-12 * step ? 0.0 : v);
    return buffer;
}

}  // namespace

bool writeSvg(const LinearPlot& plot, std::ostream& out) {
    LinearRange xs, ys;
    auto finite = [](const PlotPoint& p) { return std::isfinite(p.x) && std::isfinite(p.y); };
    for (const PlotSeries& s : plot.series) {
        for (const PlotPoint& p : s.points) {
            if (!finite(p)) continue;
            xs.widen(p.x);
            ys.widen(p.y);
        }
    }
    ys.widen(0.0);
    for (const PlotMarker& m : plot.markers)
        if (std::isfinite(m.x)) xs.widen(m.x);
    xs.finish();
    ys.finish();
    auto px = [&](double x) { return kLeft + xs.fraction(x) * (kRight - kLeft); };
    auto py = [&](double y) { return kBottom - ys.fraction(y) * (kBottom - kTop); };

    openDocument(out, plot.title);
    out << "<g stroke-width=\"1\">\n";
    for (int i = 0; xs.lo + i * xs.step <= xs.hi + 1e-9 * xs.step; ++i) {
        const double v = xs.lo + i * xs.step;
        out << "<line x1=\"" << num(px(v)) << "\" y1=\"" << kTop << "\" x2=\"" << num(px(v))
            << "\" y2=\"" << kBottom << "\" stroke=\"#ddd\"/>\n"
            << "<text x=\"" << num(px(v)) << "\" y=\"" << kBottom + 20
            << "\" text-anchor=\"middle\" stroke=\"none\">" << tickLabel(v, xs.step) << "</text>\n";
    }
    for (int i = 0; ys.lo + i * ys.step <= ys.hi + 1e-9 * ys.step; ++i) {
        const double v = ys.lo + i * ys.step;
        out << "<line x1=\"" << kLeft << "\" y1=\"" << num(py(v)) << "\" x2=\"" << kRight
            << "\" y2=\"" << num(py(v)) << "\" stroke=\"#ddd\"/>\n"
            << "<text x=\"" << kLeft - 8 << "\" y=\"" << num(py(v) + 4)
            << "\" text-anchor=\"end\" stroke=\"none\">" << tickLabel(v, ys.step) << "</text>\n";
    }
    out << "<line x1=\"" << kLeft << "\" y1=\"" << num(py(0)) << "\" x2=\"" << kRight << "\" y2=\""
        << num(py(0)) << "\" stroke=\"#333\"/>\n</g>\n";
    drawFrame(out, plot.xLabel, plot.yLabel);
    for (const PlotMarker& m : plot.markers)
        if (std::isfinite(m.x)) drawMarker(out, px(m.x), m.label);
    double legendY = kTop + 10;
    for (std::size_t i = 0; i < plot.series.size(); ++i) {
        const PlotSeries& s = plot.series[i];
        const char* colour = kColours[i % kColours.size()];
        openSeries(out, s, colour, px, py, finite);
        drawLegendEntry(out, legendY, s.name);
        out << "</g>\n";
        legendY += 20;
    }
    out << "</svg>\n";
    return static_cast<bool>(out);
}

}  // namespace plimsoll::cli
