#include "log_exp.hpp"

#include <bit>

#include "wide.hpp"

namespace sinew::fx {

// round(x 2^62), computed offline with 60-digit decimal arithmetic (Python's
// decimal module: Decimal.ln and Decimal.exp, rounded half up); checked
// against std::log2 / std::exp2 in tests/sim_core/fixed/fixed_log_exp_test.cpp.
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

constexpr uint64_t kOneQ62 = uint64_t{1} << 62;
constexpr uint64_t kLn2Q62 = 3196577161300663915u;    // ln 2, same generator
constexpr uint64_t kLog2eQ62 = 6653256548922161246u;  // 1 / ln 2
// Terms of the series: log2(1 + t), 0 <= t < 2^-5, remainder below
// log2(e) t^9 / 9 < 2^-47; 2^s = e^(s ln 2), 0 <= s < 2^-5, remainder below
// (s ln 2)^7 / 7! < 2^-51. With the roundings (about one 2^-62 per product)
// each kernel is within 2^-46 of its exact value.
constexpr int kLogTerms = 8;
constexpr int kExpTerms = 6;

// a b / 2^62, truncated (a b < 2^126).
constexpr uint64_t mul_q62(uint64_t a, uint64_t b) {
  const U128 p = mul_u64(a, b);
  return (p.hi << 2) | (p.lo >> 62);
}

// The series' coefficients in Q62: log2(e) / n, and (ln 2)^n / n!.
struct Coefficients {
  uint64_t log[kLogTerms + 1] = {};
  uint64_t exp[kExpTerms + 1] = {};
  constexpr Coefficients() {
    for (uint64_t n = 1; n <= kLogTerms; ++n) log[n] = (kLog2eQ62 + n / 2) / n;
    exp[0] = kOneQ62;
    for (uint64_t n = 1; n <= kExpTerms; ++n) exp[n] = (mul_q62(exp[n - 1], kLn2Q62) + n / 2) / n;
  }
};
constexpr Coefficients kCoefficients;

// log2(1 + t) in Q62 for 0 <= t < 2^57 (1/32): t (c1 - t (c2 - t (c3 - ...))),
// c_n = log2(e) / n; every bracket is positive (t c_(n+1) < c_n).
uint64_t log2_1p_q62(uint64_t t) {
  uint64_t p = kCoefficients.log[kLogTerms];
  for (int n = kLogTerms - 1; n >= 1; --n) p = kCoefficients.log[n] - mul_q62(t, p);
  return mul_q62(t, p);
}

// 2^s in Q62 for 0 <= s < 2^57 (1/32): sum of s^n (ln 2)^n / n!.
uint64_t exp2_small_q62(uint64_t s) {
  uint64_t p = kCoefficients.exp[kExpTerms];
  for (int n = kExpTerms - 1; n >= 0; --n) p = kCoefficients.exp[n] + mul_q62(s, p);
  return p;
}

}  // namespace

int64_t log2_q30(uint64_t v, int frac_bits) {
  if (v == 0) return kLog2OfZero;
  const int k = 63 - std::countl_zero(v);
  // m = v / 2^k in Q62, in [2^62, 2^63); v >= 2^63 drops its last bit
  // (2^-62 relative, far below the Q30 result's step).
  const uint64_t m = k <= 62 ? v << (62 - k) : v >> 1;
  const int i = static_cast<int>(m >> 57) - 32;  // m in [1 + i/32, 1 + (i+1)/32)
  // m / (1 + i/32) - 1 in [0, 2^57); the table's rounding may land a hair
  // below 1 (2^-62), read as 0.
  const uint64_t scaled = mul_q62(m, static_cast<uint64_t>(kReciprocalTableQ62[i]));
  const uint64_t t = scaled > kOneQ62 ? scaled - kOneQ62 : 0;
  const uint64_t fraction = static_cast<uint64_t>(kLog2TableQ62[i]) + log2_1p_q62(t);  // log2 m, Q62, < 2^62
  return (int64_t{k} - frac_bits) * (int64_t{1} << 30) + static_cast<int64_t>((fraction + (uint64_t{1} << 31)) >> 32);
}

int64_t exp2_fixed(int64_t x_q30, int frac_bits) {
  const int64_t n = x_q30 >> 30;                                                // floor
  const uint64_t f = static_cast<uint64_t>(x_q30) & ((uint64_t{1} << 30) - 1);  // [0, 1) in Q30
  const int j = static_cast<int>(f >> 25);
  const uint64_t s = (f & ((uint64_t{1} << 25) - 1)) << 32;  // [0, 1/32) in Q62
  // 2^(j/32) 2^s in [2^62, 2^63): 2^(1 - 2^-30) keeps it ~6e9 LSB below 2^63.
  const uint64_t m = mul_q62(static_cast<uint64_t>(kExp2TableQ62[j]), exp2_small_q62(s));
  const int64_t shift = n + frac_bits - 62;
  if (shift > 0) return INT64_MAX;
  if (shift == 0) return static_cast<int64_t>(m);
  if (shift < -62) return shift == -63 ? 1 : 0;  // m / 2^63 is in [1/2, 1): rounds up to 1
  const int r = static_cast<int>(-shift);
  return static_cast<int64_t>((m >> r) + ((m >> (r - 1)) & 1));
}

int64_t pow_fixed(uint64_t v, int v_frac, int32_t p_q16, int out_frac) {
  if (v == 0) return p_q16 > 0 ? 0 : (p_q16 == 0 ? exp2_fixed(0, out_frac) : INT64_MAX);
  // |log2 v| < 2^36 (Q30 of 64), |p| < 2^31: the product < 2^67 before the shift.
  return exp2_fixed(mul_shift_round(p_q16, log2_q30(v, v_frac), 16), out_frac);
}

}  // namespace sinew::fx
