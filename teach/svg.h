// The teaching figures' SVG (`octrace explain --svg`, `--quadtree`, `--layouts-svg`): a small
// writer of plain SVG text with one fixed number format, so a figure made twice is the same
// bytes (it can be committed and compared), and the axis plane a 2D figure is drawn in.
// SVG is plain XML text: no library is needed to write the few elements the figures use.
#pragma once

#include <string>

#include "core/geometry/ray.h"
#include "core/io/markup.h"  // xmlEscape, for the figures' text
#include "teach/colour_map.h"

namespace oct {

// A coordinate or length in the SVG: two decimals, "-0.00" written "0.00".
std::string svgNum(double v);
// "#rrggbb".
std::string svgColour(Rgb8 c);

// One SVG document of width x height user units (pixels), elements appended in drawing order.
class SvgWriter {
public:
    SvgWriter(double width, double height, const std::string& title);
    // `attrs` is further attribute text (` class="..." fill="..."`), written as given.
    void rect(double x, double y, double w, double h, const std::string& attrs);
    void line(double x0, double y0, double x1, double y1, const std::string& attrs);
    void circle(double cx, double cy, double r, const std::string& attrs);
    void polygon(const double* xy, int points, const std::string& attrs);
    void text(double x, double y, const std::string& text, const std::string& attrs);
    // An element with a tooltip: `open` is the element's start tag without its ">", closed
    // after a <title> child.
    void withTitle(const std::string& open, const std::string& element, const std::string& title);
    void raw(const std::string& markup);
    // The whole document.
    std::string finish() const;

private:
    double width_, height_;
    std::string body_;
};

// An axis plane of a 2D figure: the axes u and v it keeps (u < v) and the axis w it drops, at
// w = `at`.
struct AxisPlane {
    int u = 0, v = 1, w = 2;
    double at = 0;
    std::string name() const;  // "xy", "xz" or "yz"
};
// The plane named by --svg-plane ("xy", "xz", "yz"); TeachError naming the option, the value
// and the choices otherwise. `at` is 0.
AxisPlane parseAxisPlane(const std::string& text);
// The axis plane through the ray's origin that best holds the ray: the one that drops the axis
// of the smallest |direction| component (ties drop the later axis, so xy is kept when it can
// be). The ray lies in it exactly when that component is 0.
AxisPlane planeOfRay(const Ray& ray);
// "x", "y" or "z".
const char* axisName(int axis);

}  // namespace oct
