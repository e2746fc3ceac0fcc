#include "teach/svg.h"

#include <cmath>
#include <cstdio>

#include "teach/teach_error.h"

namespace oct {

std::string svgNum(double v) {
    char b[48];
    std::snprintf(b, sizeof b, "%.2f", v);
    std::string s = b;
    return s == "-0.00" ? "0.00" : s;
}

std::string svgColour(Rgb8 c) {
    char b[8];
    hexColour(c, b);
    return b;
}

SvgWriter::SvgWriter(double width, double height, const std::string& title)
    : width_(width), height_(height) {
    body_ = "<title>" + xmlEscape(title) + "</title>\n";
    // A white background, so the figure reads the same on a dark slide.
    body_ += "<rect x=\"0\" y=\"0\" width=\"" + svgNum(width) + "\" height=\"" + svgNum(height) +
             "\" fill=\"#ffffff\"/>\n";
}

void SvgWriter::rect(double x, double y, double w, double h, const std::string& attrs) {
    body_ += "<rect x=\"" + svgNum(x) + "\" y=\"" + svgNum(y) + "\" width=\"" + svgNum(w) +
             "\" height=\"" + svgNum(h) + "\"" + attrs + "/>\n";
}

void SvgWriter::line(double x0, double y0, double x1, double y1, const std::string& attrs) {
    body_ += "<line x1=\"" + svgNum(x0) + "\" y1=\"" + svgNum(y0) + "\" x2=\"" + svgNum(x1) +
             "\" y2=\"" + svgNum(y1) + "\"" + attrs + "/>\n";
}

void SvgWriter::circle(double cx, double cy, double r, const std::string& attrs) {
    body_ += "<circle cx=\"" + svgNum(cx) + "\" cy=\"" + svgNum(cy) + "\" r=\"" + svgNum(r) + "\"" +
             attrs + "/>\n";
}

void SvgWriter::polygon(const double* xy, int points, const std::string& attrs) {
    std::string p;
    for (int i = 0; i < points; ++i)
        p += (i ? " " : "") + svgNum(xy[2 * i]) + "," + svgNum(xy[2 * i + 1]);
    body_ += "<polygon points=\"" + p + "\"" + attrs + "/>\n";
}

void SvgWriter::text(double x, double y, const std::string& text, const std::string& attrs) {
    body_ += "<text x=\"" + svgNum(x) + "\" y=\"" + svgNum(y) + "\"" + attrs + ">" +
             xmlEscape(text) + "</text>\n";
}

void SvgWriter::withTitle(const std::string& open, const std::string& element,
                          const std::string& title) {
    body_ += open + "><title>" + xmlEscape(title) + "</title></" + element + ">\n";
}

void SvgWriter::raw(const std::string& markup) { body_ += markup; }

std::string SvgWriter::finish() const {
    return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
           "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
           svgNum(width_) + "\" height=\"" + svgNum(height_) + "\" viewBox=\"0 0 " +
           svgNum(width_) + " " + svgNum(height_) +
           "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n" + body_ + "</svg>\n";
}

const char* axisName(int axis) { return axis == 0 ? "x" : axis == 1 ? "y" : "z"; }

std::string AxisPlane::name() const { return std::string(axisName(u)) + axisName(v); }

namespace {

AxisPlane planeDropping(int w) {
    AxisPlane p;
    p.w = w;
    p.u = w == 0 ? 1 : 0;
    p.v = w == 2 ? 1 : 2;
    return p;
}

}  // namespace

AxisPlane parseAxisPlane(const std::string& text) {
    if (text == "xy") return planeDropping(2);
    if (text == "xz") return planeDropping(1);
    if (text == "yz") return planeDropping(0);
    throw TeachError("--svg-plane '" + text + "' is not an axis plane: give xy, xz or yz");
}

AxisPlane planeOfRay(const Ray& ray) {
    int w = 2;
    for (int a = 1; a >= 0; --a)
        if (std::fabs(ray.dir[a]) < std::fabs(ray.dir[w])) w = a;
    AxisPlane p = planeDropping(w);
    p.at = ray.org[w];
    return p;
}

}  // namespace oct
