#include "rfsitl/position/location_port/location_line.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

namespace rfsitl::position {
namespace {

// A published example sentence (NMEA 0183 reference texts): 48 07.038' N,
// 11 31.000' E, 545.4 m MSL, geoid separation 46.9 m; checksum 0x47.
constexpr const char* kPublishedGga =
    "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47";

// Wraps an NMEA body ("GPGGA,...") with '$', '*' and its XOR checksum.
std::string nmea(const std::string& body) {
  unsigned sum = 0;
  for (char c : body) sum ^= static_cast<unsigned char>(c);
  char hex[3];
  std::snprintf(hex, sizeof(hex), "%02X", sum);
  return "$" + body + "*" + hex;
}

GeodeticPosition expect_geodetic(std::string_view line) {
  const LocationParseResult r = parse_location_line(line);
  EXPECT_TRUE(r.error.empty()) << line << " -> " << r.error;
  EXPECT_FALSE(r.blank);
  if (!r.position || !std::holds_alternative<GeodeticPosition>(*r.position)) {
    ADD_FAILURE() << "no geodetic position from: " << line;
    return {};
  }
  return std::get<GeodeticPosition>(*r.position);
}

// The error for a rejected line (empty string, plus a test failure, if accepted).
std::string error_of(std::string_view line) {
  const LocationParseResult r = parse_location_line(line);
  EXPECT_FALSE(r.position.has_value()) << line;
  EXPECT_FALSE(r.blank) << line;
  EXPECT_FALSE(r.error.empty()) << line;
  return r.error;
}

// ---- plain numbers -------------------------------------------------------------------

TEST(LocationParser, SpaceSeparatedNumbersGiveExactGeodeticPosition) {
  const GeodeticPosition p = expect_geodetic("48.1173 11.51667 545.4");
  EXPECT_EQ(p.lat_deg, 48.1173);
  EXPECT_EQ(p.lon_deg, 11.51667);
  EXPECT_EQ(p.alt_m, 545.4);
}

TEST(LocationParser, CommaAndMixedSeparatorsAreAccepted) {
  for (const char* line : {"-33.85,151.21,-12.5", "-33.85, 151.21, -12.5", "-33.85 ,151.21 , -12.5",
                           "\t-33.85\t151.21   -12.5  ", "-33.85 151.21 -12.5\r"}) {
    const GeodeticPosition p = expect_geodetic(line);
    EXPECT_EQ(p.lat_deg, -33.85) << line;
    EXPECT_EQ(p.lon_deg, 151.21) << line;
    EXPECT_EQ(p.alt_m, -12.5) << line;
  }
}

TEST(LocationParser, LeadingPlusSignAndRangeLimitsAreAccepted) {
  const GeodeticPosition hi = expect_geodetic("+90 180 100000");
  EXPECT_EQ(hi.lat_deg, 90.0);
  EXPECT_EQ(hi.lon_deg, 180.0);
  EXPECT_EQ(hi.alt_m, 100000.0);
  const GeodeticPosition lo = expect_geodetic("-90 -180 -1000");
  EXPECT_EQ(lo.lat_deg, -90.0);
  EXPECT_EQ(lo.lon_deg, -180.0);
  EXPECT_EQ(lo.alt_m, -1000.0);
}

TEST(LocationParser, BlankLinesAreBlankNotErrors) {
  for (const char* line : {"", "   ", "\r", " \t \r"}) {
    const LocationParseResult r = parse_location_line(line);
    EXPECT_TRUE(r.blank) << '"' << line << '"';
    EXPECT_FALSE(r.position.has_value());
    EXPECT_TRUE(r.error.empty());
  }
}

TEST(LocationParser, WrongNumberCountIsRejectedWithCount) {
  EXPECT_EQ(error_of("48.1 11.5"), "expected 3 numbers (lat lon alt), got 2");
  EXPECT_EQ(error_of("48.1 11.5 100 7"), "expected 3 numbers (lat lon alt), got 4");
}

TEST(LocationParser, NonNumericFieldIsRejectedNamingTheField) {
  EXPECT_EQ(error_of("48.1 east 100"), "longitude 'east' is not a number");
  EXPECT_EQ(error_of("48.1 11.5 100m"), "altitude '100m' is not a number");
  EXPECT_EQ(error_of("0x10 11.5 100"), "latitude '0x10' is not a number");
}

TEST(LocationParser, EmptyCommaSeparatedFieldIsRejected) {
  EXPECT_EQ(error_of("48.1,,100"), "empty field 2");
  EXPECT_EQ(error_of("48.1,11.5,100,"), "empty field 4");
}

TEST(LocationParser, OutOfRangeValuesAreRejectedNamingFieldAndRange) {
  EXPECT_EQ(error_of("91.5 0 0"), "latitude 91.5 out of range [-90, 90]");
  EXPECT_EQ(error_of("-90.5 0 0"), "latitude -90.5 out of range [-90, 90]");
  EXPECT_EQ(error_of("0 180.5 0"), "longitude 180.5 out of range [-180, 180]");
  EXPECT_EQ(error_of("0 -181 0"), "longitude -181 out of range [-180, 180]");
  EXPECT_EQ(error_of("0 0 -1000.5"), "altitude -1000.5 out of range [-1000, 100000]");
  EXPECT_EQ(error_of("0 0 100001"), "altitude 100001 out of range [-1000, 100000]");
}

TEST(LocationParser, NanAndInfinityAreRejected) {
  EXPECT_EQ(error_of("nan 0 0"), "latitude is not a finite number (nan)");
  EXPECT_EQ(error_of("0 inf 0"), "longitude is not a finite number (inf)");
  EXPECT_EQ(error_of("0 0 -infinity"), "altitude is not a finite number (-inf)");
}

// ---- JSON ------------------------------------------------------------------------------

TEST(LocationParser, JsonLatLonAltGivesExactGeodeticPosition) {
  const GeodeticPosition p = expect_geodetic(R"({"lat": 48.1173, "lon": 11.51667, "alt": 545.4})");
  EXPECT_EQ(p.lat_deg, 48.1173);
  EXPECT_EQ(p.lon_deg, 11.51667);
  EXPECT_EQ(p.alt_m, 545.4);
}

TEST(LocationParser, JsonAltIsOptionalAndIntegersAndExtraKeysAreAccepted) {
  const GeodeticPosition p = expect_geodetic(R"( {"id":3,"lat":-45,"lon":170} )"
                                             "\r");
  EXPECT_EQ(p.lat_deg, -45.0);
  EXPECT_EQ(p.lon_deg, 170.0);
  EXPECT_EQ(p.alt_m, 0.0);
}

TEST(LocationParser, JsonXyzGivesLocalPosition) {
  const LocationParseResult r = parse_location_line(R"({"x": 120.5, "y": -40, "z": 15.25})");
  ASSERT_TRUE(r.position.has_value()) << r.error;
  ASSERT_TRUE(std::holds_alternative<LocalPosition>(*r.position));
  const auto& p = std::get<LocalPosition>(*r.position);
  EXPECT_EQ(p.x_m, 120.5);
  EXPECT_EQ(p.y_m, -40.0);
  EXPECT_EQ(p.z_m, 15.25);

  const LocationParseResult no_z = parse_location_line(R"({"x": 1, "y": 2})");
  ASSERT_TRUE(no_z.position.has_value()) << no_z.error;
  EXPECT_EQ(std::get<LocalPosition>(*no_z.position).z_m, 0.0);
}

TEST(LocationParser, MalformedJsonIsRejected) {
  EXPECT_EQ(error_of(R"({"lat": 48.1, "lon": )").rfind("malformed JSON", 0), 0u);
  EXPECT_EQ(error_of(R"({"lat": 48.1, "lon": 11} trailing)").rfind("malformed JSON", 0), 0u);
  EXPECT_EQ(error_of("[48.1, 11.5, 100]"), "JSON value is not an object");
}

TEST(LocationParser, JsonMissingKeyIsRejectedNamingTheKey) {
  EXPECT_EQ(error_of(R"({"lon": 11.5, "alt": 3})"), R"(JSON object missing key "lat")");
  EXPECT_EQ(error_of(R"({"lat": 48.1})"), R"(JSON object missing key "lon")");
  EXPECT_EQ(error_of(R"({"x": 1, "z": 3})"), R"(JSON object missing key "y")");
  EXPECT_EQ(error_of(R"({"speed": 3})"), "JSON object has neither lat/lon/alt nor x/y/z keys");
}

TEST(LocationParser, JsonMixingGeodeticAndLocalKeysIsRejected) {
  EXPECT_EQ(error_of(R"({"lat": 1, "lon": 2, "z": 3})"),
            "JSON object mixes lat/lon/alt with x/y/z keys");
}

TEST(LocationParser, JsonNonNumericValueIsRejectedNamingTheKey) {
  EXPECT_EQ(error_of(R"({"lat": "48.1", "lon": 11})"), R"(JSON key "lat" is not a number)");
  EXPECT_EQ(error_of(R"({"lat": 48.1, "lon": true})"), R"(JSON key "lon" is not a number)");
  EXPECT_EQ(error_of(R"({"lat": 48.1, "lon": 11, "alt": null})"),
            R"(JSON key "alt" is not a number)");
}

TEST(LocationParser, JsonValuesAreRangeChecked) {
  EXPECT_EQ(error_of(R"({"lat": 91.5, "lon": 0})"), "latitude 91.5 out of range [-90, 90]");
  EXPECT_EQ(error_of(R"({"x": 0, "y": 0, "z": 200000})"), "z 200000 out of range [-1000, 100000]");
  EXPECT_EQ(error_of(R"({"x": 1e999, "y": 0})"), "JSON number out of range");
  // Finite is not enough for local x, y: the tangent plane ends 10 000 km out.
  EXPECT_EQ(error_of(R"({"x": 1.7e308, "y": 0})"), "x 1.7e+308 out of range [-10000000, 10000000]");
  EXPECT_TRUE(parse_location_line(R"({"x": 0, "y": -1e7})").position.has_value());
  EXPECT_EQ(error_of(R"({"x": 0, "y": -10000001})"),
            "y -10000001 out of range [-10000000, 10000000]");
}

// ---- NMEA GGA --------------------------------------------------------------------------

TEST(LocationParser, ChecksumHelperReproducesPublishedChecksum) {
  EXPECT_EQ(nmea("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"), kPublishedGga);
}

TEST(LocationParser, PublishedGgaSentenceGivesEllipsoidalPosition) {
  const GeodeticPosition p = expect_geodetic(kPublishedGga);
  EXPECT_NEAR(p.lat_deg, 48.1173, 1e-12);
  EXPECT_NEAR(p.lon_deg, 11.0 + 31.0 / 60.0, 1e-12);
  EXPECT_NEAR(p.alt_m, 545.4 + 46.9, 1e-9);  // MSL altitude + geoid separation
}

TEST(LocationParser, GgaWithTrailingCarriageReturnIsAccepted) {
  const GeodeticPosition p = expect_geodetic(std::string(kPublishedGga) + "\r");
  EXPECT_NEAR(p.lat_deg, 48.1173, 1e-12);
}

TEST(LocationParser, GgaSouthWestHemispheresGiveNegativeDegrees) {
  const GeodeticPosition p =
      expect_geodetic(nmea("GNGGA,010203.00,3351.0000,S,15112.6000,W,2,12,0.7,-20.5,M,-3.5,M,,"));
  EXPECT_NEAR(p.lat_deg, -(33.0 + 51.0 / 60.0), 1e-12);
  EXPECT_NEAR(p.lon_deg, -(151.0 + 12.6 / 60.0), 1e-12);
  EXPECT_NEAR(p.alt_m, -24.0, 1e-12);
}

TEST(LocationParser, GgaFromAnyTwoLetterTalkerIsAccepted) {
  for (const char* talker : {"GL", "GA", "BD"}) {
    const GeodeticPosition p = expect_geodetic(
        nmea(std::string(talker) + "GGA,120000,0030.000,N,00015.000,E,1,05,1.0,10.0,M,0.0,M,,"));
    EXPECT_NEAR(p.lat_deg, 0.5, 1e-12) << talker;
    EXPECT_NEAR(p.lon_deg, 0.25, 1e-12) << talker;
    EXPECT_NEAR(p.alt_m, 10.0, 1e-12) << talker;
  }
}

TEST(LocationParser, GgaLowercaseChecksumAndEmptyGeoidSeparationAreAccepted) {
  std::string line = nmea("GPGGA,120000,4500.000,N,00700.000,E,1,05,1.0,250.0,M,,M,,");
  ASSERT_EQ(line.substr(line.size() - 3), "*5A");  // a checksum with a letter in it
  line.back() = 'a';
  const GeodeticPosition p = expect_geodetic(line);
  EXPECT_NEAR(p.lat_deg, 45.0, 1e-12);
  EXPECT_NEAR(p.lon_deg, 7.0, 1e-12);
  EXPECT_NEAR(p.alt_m, 250.0, 1e-12);  // unknown separation counts as 0
}

TEST(LocationParser, GgaChecksumMismatchIsRejectedWithBothValues) {
  std::string bad = kPublishedGga;
  bad.replace(bad.size() - 2, 2, "48");
  EXPECT_EQ(error_of(bad), "NMEA checksum mismatch: computed 47, line says 48");
  std::string corrupted = kPublishedGga;
  corrupted[20] = '9';  // 4807.038 -> 4807.098: one flipped digit
  EXPECT_EQ(error_of(corrupted).rfind("NMEA checksum mismatch: computed ", 0), 0u);
}

TEST(LocationParser, GgaWithoutChecksumIsRejected) {
  EXPECT_EQ(error_of("$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
            "NMEA sentence without checksum");
  EXPECT_EQ(error_of("$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*4"),
            "NMEA checksum '4' is not two hex digits");
}

TEST(LocationParser, GgaWithoutFixIsRejected) {
  EXPECT_EQ(error_of(nmea("GPGGA,002153.000,,,,,0,00,,,M,,M,,")),
            "NMEA GGA fix quality 0 (no fix)");
  EXPECT_EQ(error_of(nmea("GPGGA,123519,4807.038,N,01131.000,E,0,08,0.9,545.4,M,46.9,M,,")),
            "NMEA GGA fix quality 0 (no fix)");
}

TEST(LocationParser, UnsupportedNmeaSentenceIsRejectedNamingIt) {
  // Published RMC example with its known checksum.
  EXPECT_EQ(error_of("$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A"),
            "unsupported NMEA sentence GPRMC");
  EXPECT_EQ(error_of(nmea("PGRMZ,246,f,3")), "unsupported NMEA sentence PGRMZ");
}

TEST(LocationParser, MalformedGgaFieldsAreRejectedNamingTheField) {
  EXPECT_EQ(error_of(nmea("GPGGA,123519,48.07,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,")),
            "NMEA GGA latitude '48.07' is not ddmm.mmmm");
  EXPECT_EQ(error_of(nmea("GPGGA,123519,4807.038,X,01131.000,E,1,08,0.9,545.4,M,46.9,M,,")),
            "NMEA GGA latitude hemisphere 'X' is not N or S");
  EXPECT_EQ(error_of(nmea("GPGGA,123519,4807.038,N,01131.000,,1,08,0.9,545.4,M,46.9,M,,")),
            "NMEA GGA longitude hemisphere '' is not E or W");
  EXPECT_EQ(error_of(nmea("GPGGA,123519,4867.000,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,")),
            "NMEA GGA latitude minutes 67 out of range [0, 60)");
  EXPECT_EQ(error_of(nmea("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,1789.4,F,46.9,M,,")),
            "NMEA GGA altitude unit 'F' is not M");
  EXPECT_EQ(error_of(nmea("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,,M,46.9,M,,")),
            "NMEA GGA altitude field is empty");
  EXPECT_EQ(error_of(nmea("GPGGA,123519,4807.038,N,01131.000,E,1,08")),
            "NMEA GGA sentence has 8 fields, expected 15");
}

TEST(LocationParser, GgaPositionIsRangeChecked) {
  EXPECT_EQ(error_of(nmea("GPGGA,123519,9130.000,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,")),
            "latitude 91.5 out of range [-90, 90]");
  EXPECT_EQ(error_of(nmea("GPGGA,123519,4807.038,N,18030.000,W,1,08,0.9,545.4,M,46.9,M,,")),
            "longitude -180.5 out of range [-180, 180]");
  EXPECT_EQ(error_of(nmea("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,99990.0,M,46.9,M,,")),
            "altitude 100036.9 out of range [-1000, 100000]");
}

// ---- robustness ------------------------------------------------------------------------

// Every line yields exactly one of position, error or blank, and nothing throws,
// however a valid line is truncated or corrupted.
TEST(LocationParser, TruncatedAndCorruptedLinesNeverThrowAndAlwaysClassify) {
  const std::string seeds[] = {kPublishedGga, R"({"lat": 48.1, "lon": 11.5, "alt": 3})",
                               "48.1173, 11.51667, 545.4", R"({"x": 1, "y": 2, "z": 3})"};
  std::mt19937 rng(5);
  const std::string junk = "$*,{}[]\":.-+eE0123456789NSEWM \r\t\x01\xff";
  for (const std::string& seed : seeds) {
    for (std::size_t cut = 0; cut <= seed.size(); ++cut) {
      for (int variant = 0; variant < 8; ++variant) {
        std::string line = seed.substr(0, cut);
        if (variant > 0 && !line.empty()) line[rng() % line.size()] = junk[rng() % junk.size()];
        LocationParseResult r;
        ASSERT_NO_THROW(r = parse_location_line(line)) << line;
        const int kinds = int(r.position.has_value()) + int(!r.error.empty()) + int(r.blank);
        EXPECT_EQ(kinds, 1) << line;
      }
    }
  }
}

}  // namespace
}  // namespace rfsitl::position
