#pragma once
// The paper's published figures (Clouse & Padgett, paper 002), for the
// benchmark to print beside ours. Figures 3-5 are plots without printed
// values; their text is quoted instead.

namespace ephor::sphere::paper {

constexpr double kDistancesM[6] = {1, 2, 5, 10, 15, 20};

// Table 2: half angular extent (deg) and frames per 0.5 s trial.
constexpr double kTable2HalfExtentDeg[6] = {5.22, 2.65, 1.12, 0.60, 0.43, 0.35};
constexpr double kTable2Frames[6] = {0.48, 0.95, 2.23, 4.14, 5.77, 7.20};

// Table 1: total x and y speed (cm/s) as printed (the 2 m row's columns sum to 3.3).
constexpr double kTable1TotalCmS[6] = {2.7, 4.1, 5.1, 8.1, 11.1, 14.1};

// Table 3: Sphere Fitting CPU time per trial (s), min and max of 200, on a
// 200 MHz Pentium Pro.
constexpr double kTable3MinS[6] = {0.08, 0.11, 0.09, 0.08, 0.04, 0.06};
constexpr double kTable3MaxS[6] = {0.87, 0.28, 0.18, 0.20, 0.13, 0.12};

// Table 4 (captioned "Sphere Fitting" in the paper, but it is the Scan Line
// Extent table the text describes): CPU time per trial (s), same machine.
constexpr double kTable4MinS[6] = {0.0063, 0.0062, 0.0075, 0.0085, 0.0086, 0.0084};
constexpr double kTable4MaxS[6] = {0.0070, 0.0077, 0.0096, 0.0107, 0.0095, 0.0093};

// Figures 3-5 in words (section 5).
constexpr const char* kFigure3 =
    "Sphere Fitting: x bias and noise well within 8 mm at all distances; z fails at all "
    "distances (biased toward the sensor, high noise); y within except at 1 m";
constexpr const char* kFigure4 =
    "Scan Line Extent: all noise values under 8 mm; x smallest; y noise and bias up at 1 m "
    "(less than a frame); z underestimated, growing with distance";
constexpr const char* kFigure5 = "Scan Line Extent velocity error: plotted, no requirement";

}  // namespace ephor::sphere::paper
