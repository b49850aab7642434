// Small hand-written SVG line plots: log-log axes for the benchmark's speed/accuracy chart,
// linear axes for curves that cross zero (hydrostatics' righting arms);
// no plotting library, one self-contained file any browser shows.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace plimsoll::cli {

struct PlotPoint {
    /// Both > 0: a point at x <= 0 or y <= 0 cannot sit on log axes and is left out.
    double x = 0;
    double y = 0;
    std::string label;  ///< drawn beside the point
};

/// One polyline with its markers, in the order given.
struct PlotSeries {
    std::string name;  ///< legend entry
    std::vector<PlotPoint> points;
};

/// A vertical dashed line across the plot (a reference value of x, such as a baseline's time).
struct PlotMarker {
    double x = 0;
    std::string label;
};

struct LogLogPlot {
    std::string title;
    std::string xLabel;
    std::string yLabel;
    std::vector<PlotSeries> series;
    std::vector<PlotMarker> markers;
};

/// Writes a complete SVG document; the axes span whole decades around every point and marker.
/// Returns false only when the stream fails.
bool writeSvg(const LogLogPlot& plot, std::ostream& out);

}  // namespace plimsoll::cli

namespace plimsoll::cli {

/// The same plot on linear axes (curves that cross zero, such as a righting-arm curve): the
/// series, markers and legend as on log-log axes, a grid at round steps and a line at y = 0.
/// Points that are not finite are left out.
struct LinearPlot {
    std::string title;
    std::string xLabel;
    std::string yLabel;
    std::vector<PlotSeries> series;
    std::vector<PlotMarker> markers;
};

bool writeSvg(const LinearPlot& plot, std::ostream& out);

}  // namespace plimsoll::cli
