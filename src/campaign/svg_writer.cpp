#include "rfsitl/campaign/svg_writer.hpp"

#include <cmath>
#include <cstdio>

namespace rfsitl::campaign {

SvgWriter::SvgWriter(double width, double height) : width_(width), height_(height) {}

std::string SvgWriter::number(double v) {
  // Two decimals are finer than a pixel; trailing zeros dropped.
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", std::fabs(v) < 0.005 ? 0.0 : v);
  std::string s = buf;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s;
}

std::string SvgWriter::escaped(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void SvgWriter::line(double x1, double y1, double x2, double y2, std::string_view style) {
  body_ += "<line x1=\"" + number(x1) + "\" y1=\"" + number(y1) + "\" x2=\"" + number(x2) +
           "\" y2=\"" + number(y2) + "\" " + std::string(style) + "/>\n";
}

void SvgWriter::polyline(const std::string& points, std::string_view style) {
  body_ += "<polyline fill=\"none\" points=\"" + points + "\" " + std::string(style) + "/>\n";
}

void SvgWriter::circle(double cx, double cy, double r, std::string_view style) {
  body_ += "<circle cx=\"" + number(cx) + "\" cy=\"" + number(cy) + "\" r=\"" + number(r) + "\" " +
           std::string(style) + "/>\n";
}

void SvgWriter::rect(double x, double y, double w, double h, std::string_view style) {
  body_ += "<rect x=\"" + number(x) + "\" y=\"" + number(y) + "\" width=\"" + number(w) +
           "\" height=\"" + number(h) + "\" " + std::string(style) + "/>\n";
}

void SvgWriter::text(double x, double y, std::string_view content, std::string_view anchor,
                     std::string_view style) {
  body_ += "<text x=\"" + number(x) + "\" y=\"" + number(y) + "\" text-anchor=\"" +
           std::string(anchor) + "\" " + std::string(style) + ">" + escaped(content) + "</text>\n";
}

void SvgWriter::raw(std::string_view element) {
  body_ += element;
  body_ += '\n';
}

std::string SvgWriter::finish() const {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
         number(width_) + "\" height=\"" + number(height_) + "\" viewBox=\"0 0 " + number(width_) +
         " " + number(height_) + "\" font-family=\"sans-serif\" font-size=\"12\">\n" + body_ +
         "</svg>\n";
}

}  // namespace rfsitl::campaign
