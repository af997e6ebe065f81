// Decimal text <-> double for the text formats (TRC) and the CLI, locale-independent.
#pragma once

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

}  // namespace capz
