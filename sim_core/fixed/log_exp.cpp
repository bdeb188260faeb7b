#include "log_exp.hpp"

#include <bit>

#include "scalar.hpp"
#include "wide.hpp"

namespace sinew::fx {

// round(x 2^62), computed offline with 60-digit decimal arithmetic (Python's
// decimal module: Decimal.ln and Decimal.exp, rounded half up); checked
// against std::log2 / std::exp2 in tests/unit/fixed_log_exp_test.cpp.
const int64_t kReciprocalTableQ62[kLogExpTableSize] = {
    // 1 / (1 + i/32)
    4611686018427387904, 4471937957262921604, 4340410370284600380, 4216398645419326084, 4099276460824344804,
    3988485205126389539, 3883525068149379288, 3783947502299395203, 3689348814741910323, 3599364697309180803,
    3513665537849438403, 3431952385806428208, 3353953467947191203, 3279421168659475843, 3208129404123400281,
    3139871331695242828, 3074457345618258603, 3011713318156661488, 2951479051793528259, 2893606913523066920,
    2837960626724546402, 2784414199805215338, 2732850973882896536, 2683162774357752962, 2635249153387078802,
    2589016712099586192, 2544378492925455395, 2501253433723329033, 2459565876494606882, 2419245124420924802,
    2380225041768974402, 2342443691899625602,
};
const int64_t kLog2TableQ62[kLogExpTableSize] = {
    // log2(1 + i/32)
    0,
    204731739545776358,
    403351162126124447,
    596212681665212875,
    783640753332765648,
    965933157783587320,
    1143363847331251474,
    1316185422355184002,
    1484631294131014398,
    1648917580557901400,
    1809244773414275253,
    1965799209408045220,
    2118754372093087486,
    2268272047463780046,
    2414503352528620721,
    2557589653257460679,
    2697663385880076776,
    2834848793495784858,
    2969262588262028797,
    3101014548006201223,
    3230208054902495130,
    3356940582836414350,
    3481304139212842424,
    3603385666224101885,
    3723267405961586381,
    3841027233211328250,
    3956738959306241175,
    4070472610004118119,
    4182294680011091174,
    4292268366467094717,
    4400453783446152532,
    4506908159294352029,
};
const int64_t kExp2TableQ62[kLogExpTableSize] = {
    // 2^(i/32)
    4611686018427387904, 4712668792719003884, 4815862801830788490, 4921316465500308116, 5029079263719320435,
    5139201759950318048, 5251735624851448219, 5366733660520940721, 5484249825272419512, 5604339258952723100,
    5727058308814112983, 5852464555953009676, 5980616842327661685, 6111575298367424380, 6245401371186603363,
    6382157853416100552, 6521908912666391106, 6664720121635655541, 6810658488877194079, 6959792490240559659,
    7112192101001162095, 7267928828693418961, 7427075746662858866, 7589707528352920109, 7755900482342532474,
    7925732588150922155, 8099283532826439817, 8276634748336579668, 8457869449776733335, 8643072674415606502,
    8832331321595618838, 9025734193507008925,
};

namespace {

constexpr int64_t kOneQ62 = int64_t{1} << 62;
constexpr int64_t kLn2Q62 = 3196577161300663915;    // ln 2, same generator
constexpr int64_t kLog2eQ62 = 6653256548922161246;  // 1 / ln 2
constexpr int kLnTerms = 10;                        // |t| < 2^-5: remainder |t|^11 / 11 < 2^-58
constexpr int kExpTerms = 8;                        // s ln 2 < 2^-5.5: remainder < 2^-68

// round(2^62 / n) and round(2^62 / n!): the series' coefficients.
struct Coefficients {
  int64_t inverse[kLnTerms + 1] = {};
  int64_t inverse_factorial[kExpTerms + 1] = {};
  constexpr Coefficients() {
    int64_t factorial = 1;
    for (int64_t n = 1; n <= kLnTerms; ++n) inverse[n] = (kOneQ62 + n / 2) / n;
    for (int64_t n = 0; n <= kExpTerms; ++n) {
      if (n > 0) factorial *= n;
      inverse_factorial[n] = (kOneQ62 + factorial / 2) / factorial;
    }
  }
};
constexpr Coefficients kCoefficients;

inline int64_t mul_q62(int64_t a, int64_t b) { return mul_shift_round(a, b, 62); }

// ln(1 + t) in Q62 for |t| <= 2^57 (1/32): t (1 - t (1/2 - t (1/3 - ...))).
int64_t ln1p_q62(int64_t t) {
  int64_t p = kCoefficients.inverse[kLnTerms];
  for (int n = kLnTerms - 1; n >= 1; --n) p = kCoefficients.inverse[n] - mul_q62(t, p);
  return mul_q62(t, p);
}

// e^w in Q62 for 0 <= w < 2^57: sum of w^n / n!, n <= 8.
int64_t exp_q62(int64_t w) {
  int64_t p = kCoefficients.inverse_factorial[kExpTerms];
  for (int n = kExpTerms - 1; n >= 0; --n) p = kCoefficients.inverse_factorial[n] + mul_q62(w, p);
  return p;
}

}  // namespace

int64_t log2_q30(uint64_t v, int frac_bits) {
  if (v == 0) return kLog2OfZero;
  const int k = 63 - std::countl_zero(v);
  // m = v / 2^k in Q62, in [2^62, 2^63); v >= 2^63 drops its last bit
  // (2^-62 relative, far below the Q30 result's step).
  const int64_t m = static_cast<int64_t>(k <= 62 ? v << (62 - k) : v >> 1);
  const int i = static_cast<int>(m >> 57) - 32;                                 // m in [1 + i/32, 1 + (i+1)/32)
  const int64_t t = mul_q62(m, kReciprocalTableQ62[i]) - kOneQ62;               // m / (1 + i/32) - 1, in [-1 LSB, 2^57)
  const int64_t fraction = kLog2TableQ62[i] + mul_q62(ln1p_q62(t), kLog2eQ62);  // log2 m, Q62, [0, 2^62)
  return (int64_t{k} - frac_bits) * (int64_t{1} << 30) + round_shift(fraction, 32);
}

int64_t exp2_fixed(int64_t x_q30, int frac_bits) {
  const int64_t n = x_q30 >> 30;                       // floor
  const int64_t f = x_q30 & ((int64_t{1} << 30) - 1);  // [0, 1) in Q30
  const int j = static_cast<int>(f >> 25);
  const int64_t s = f & ((int64_t{1} << 25) - 1);  // [0, 1/32) in Q30
  const int64_t w = mul_shift_round(s, kLn2Q62, 30);
  // 2^(j/32) e^w in [2^62, 2^63): 2^(1 - 2^-30) keeps it ~6e9 LSB below 2^63.
  const int64_t m = mul_q62(kExp2TableQ62[j], exp_q62(w));
  const int64_t shift = n + frac_bits - 62;
  if (shift > 0) return INT64_MAX;
  if (shift == 0) return m;
  if (shift < -62) return shift == -63 ? 1 : 0;  // m / 2^63 is in [1/2, 1): rounds up to 1
  return round_shift(m, static_cast<int>(-shift));
}

int64_t pow_fixed(uint64_t v, int v_frac, int32_t p_q16, int out_frac) {
  if (v == 0) return p_q16 > 0 ? 0 : (p_q16 == 0 ? exp2_fixed(0, out_frac) : INT64_MAX);
  // |log2 v| < 2^36 (Q30 of 64), |p| < 2^31: the product < 2^67 before the shift.
  return exp2_fixed(mul_shift_round(p_q16, log2_q30(v, v_frac), 16), out_frac);
}

}  // namespace sinew::fx
