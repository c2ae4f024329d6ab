#pragma once
/// 3GPP TR 36.777 (v15.0.0) Annex B: the urban channel of aerial UEs (drones)
/// seen from ground base stations, UMa-AV and UMi-AV. Each scenario has an
/// aerial form above 22.5 m (Tables B-1, B-2, B-3) and, at or below 22.5 m, the
/// terrestrial TR 38.901 (v14) UMa / UMi-Street-Canyon form the annex points to
/// (Tables 7.4.1-1 and 7.4.2-1, outdoor UE).
///
/// Pure functions of the link's geometry: no state, thread-safe. Conventions:
/// distances and heights in metres, the carrier in Hz (converted to GHz inside,
/// as the TRs' log10(fc) terms want), losses and deviations in dB.
/// Preconditions of every function: heights finite and >= kMinUtHeightM (the
/// breakpoint's effective heights h - 1 m must be positive), d2d_m finite and
/// >= 0, carrier_hz > 0, and the straight-line distance
/// d3D = sqrt(d2D^2 + (h_bs - h_ut)^2) > 0. The rest of the TRs' validity
/// (UE height <= 300 m, d2D 10 m..5 km terrestrial, <= 4 km aerial, base
/// station 25 m UMa / 10 m UMi, fc 0.5..100 GHz) is the caller's to enforce;
/// outside it the formulas are extrapolated as written.
namespace rfsitl::channel::path_loss::tr36777 {

enum class Scenario {
  kUmaAv,  ///< urban macro: TR 38.901 UMa, base station nominally 25 m high
  kUmiAv,  ///< urban micro: TR 38.901 UMi-Street-Canyon, base station nominally 10 m high
};

/// The UE heights the TRs cover: 1.5 m (terrestrial) to 300 m (aerial).
inline constexpr double kMinUtHeightM = 1.5;
inline constexpr double kMaxUtHeightM = 300.0;
/// At or below this UE height the terrestrial TR 38.901 formulas apply, above
/// it the aerial ones (TR 36.777 writes the bands "<= 22.5" / "22.5 <").
inline constexpr double kTerrestrialMaxHeightM = 22.5;

/// P_LOS(d2D, h_UT), in [0, 1] (TR 36.777 Table B-1; at or below 22.5 m, TR
/// 38.901 Table 7.4.2-1). UMa-AV is 1 above 100 m.
double los_probability(Scenario scenario, double d2d_m, double h_ut_m);

/// The mean path loss in dB, line of sight or not (TR 36.777 Table B-2; at or
/// below 22.5 m, TR 38.901 Table 7.4.1-1 with the effective environment height
/// h_E fixed at 1 m: see tr36777.cpp). Shadow fading is not included.
double path_loss_db(Scenario scenario, bool line_of_sight, double d2d_m, double h_bs_m,
                    double h_ut_m, double carrier_hz);

/// The log-normal shadow fading's standard deviation in dB that goes with
/// path_loss_db (TR 36.777 Table B-3; TR 38.901 Table 7.4.1-1). For a
/// shadowing stage to draw: path_loss_db does not apply it.
double shadow_fading_sigma_db(Scenario scenario, bool line_of_sight, double h_ut_m);

}  // namespace rfsitl::channel::path_loss::tr36777
