#pragma once
/// A small SVG document writer: the shapes a line plot needs, text escaped,
/// numbers written the same way every time.
#include <string>
#include <string_view>

namespace rfsitl::campaign {

class SvgWriter {
 public:
  SvgWriter(double width, double height);

  /// `style`: the element's attributes beyond its geometry, written as given
  /// (e.g. `stroke="#333" stroke-width="1"`).
  void line(double x1, double y1, double x2, double y2, std::string_view style);
  /// Points as "x,y x,y ...": polyline_points() builds them.
  void polyline(const std::string& points, std::string_view style);
  void circle(double cx, double cy, double r, std::string_view style);
  void rect(double x, double y, double w, double h, std::string_view style);
  /// `anchor`: start, middle or end.
  void text(double x, double y, std::string_view content, std::string_view anchor,
            std::string_view style = "");
  /// Any element written as given (e.g. a <g> with data attributes).
  void raw(std::string_view element);

  /// The document, closed.
  std::string finish() const;

  static std::string number(double v);                ///< "12.5", "-3"
  static std::string escaped(std::string_view text);  ///< &, <, >, " as entities

 private:
  std::string body_;
  double width_;
  double height_;
};

}  // namespace rfsitl::campaign
