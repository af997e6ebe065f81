// Decimal text <-> double for the text formats (TRC) and the CLI, locale-independent.
#pragma once

#include <cstdint>
#include <string>

namespace capz {

// Parses the whole of `s` (no surrounding blanks) as a decimal number: optional sign, digits,
// fraction, exponent, or nan/inf in any case. Returns false if anything is left over or empty.
// Correctly rounded (std::from_chars).
bool parse_double(const std::string& s, double* out);

// The shortest fixed-point text that parses back to exactly `v`, padded with zeros to at least
// `min_decimals` digits after the point (none when min_decimals <= 0 and v is integral).
// Values whose fixed form would exceed 40 characters use exponent form; NaN gives "NaN".
std::string format_decimal(double v, int min_decimals);

// format_decimal(v, decimals) when that text has at most `decimals` digits after the point (every
// value a text with `decimals` decimals gave), else `v` correctly rounded to `decimals` decimals
// (`%.*f`): the coordinates of a take decoded at a bound, printed as the source printed its
// own. decimals < 0: format_decimal(v, 0).
std::string format_decimal_rounded(double v, int decimals);

// Number spellings of text other tools write (ascii PCD bodies, docs/FORMAT.md 14.6), for a
// finite value. `precision` is used by kStyleG/E/F only.
enum NumberStyle : uint8_t {
  kStyleShortest = 0,        // shortest text reading back to the value in its own type (float32
                             // when `single`), fixed or exponent form, whichever is shorter
                             // (std::to_chars): capz's PCD writer
  kStylePythonDouble = 1,    // Python's repr of the value as a double: "0.1", "1e-05", "3.0"
  kStylePythonShortest = 2,  // Python's repr layout with the shortest digits of the value's own
                             // type (numpy's str of a float32)
  kStyleG = 3,  // printf "%.{precision}g" of the value as a double (PCL: 8, Open3D: 10)
  kStyleE = 4,  // printf "%.{precision}e" (numpy savetxt's default: 18)
  kStyleF = 5,  // printf "%.{precision}f"
};
constexpr uint8_t kNumberStyles = 6;
constexpr uint8_t kMaxStylePrecision = 40;

// Appends finite `v` spelled in `style` (< kNumberStyles; precision <= kMaxStylePrecision);
// `single`: v is a float32 (its shortest digits are float32's).
void append_styled(double v, bool single, uint8_t style, uint8_t precision, std::string* out);

}  // namespace capz
