#include "gpu/spirv_device_model.h"

#include <glslang/SPIRV/GLSL.std.450.h>

#include <bit>
#include <cstring>
#include <glslang/SPIRV/spirv.hpp>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>

#include "core/device_precision.h"

namespace hdrc::gpu {

namespace {

// One instruction: its words, the first holding (word count << 16) | opcode (SPIR-V spec, 2.3
// "Physical Layout of a SPIR-V Module and Instruction").
struct Inst {
  std::vector<uint32_t> w;
  spv::Op op() const { return static_cast<spv::Op>(w[0] & 0xffffu); }
};

Inst make(spv::Op op, std::initializer_list<uint32_t> operands) {
  Inst i;
  i.w.reserve(operands.size() + 1);
  i.w.push_back((static_cast<uint32_t>(operands.size() + 1) << 16) | static_cast<uint32_t>(op));
  i.w.insert(i.w.end(), operands);
  return i;
}

// The literal string operand starting at word `at` (nul-terminated, padded to words).
std::string literal_string(const Inst& i, size_t at) {
  std::string s;
  for (size_t k = at; k < i.w.size(); ++k)
    for (int b = 0; b < 4; ++b) {
      const char c = static_cast<char>((i.w[k] >> (8 * b)) & 0xffu);
      if (c == '\0') return s;
      s.push_back(c);
    }
  return s;
}

class Rewriter {
 public:
  Status parse(const std::vector<uint32_t>& code);
  DeviceModelRewrite run();
  std::vector<uint32_t> assemble() const;

 private:
  // Types: float32 scalar/vector → component count; lookup and synthesis of uint/bool vectors.
  int float32_components(uint32_t type) const;
  uint32_t type_uint(int n);
  uint32_t type_bool(int n);
  uint32_t type_float(int n);
  uint32_t const_u(uint32_t value, int n);
  uint32_t const_f(float value, int n);
  uint32_t splat(uint32_t vector_type, uint32_t scalar, int n);
  uint32_t glsl();

  uint32_t fresh() { return bound_++; }
  // Appends `op %type %id operands...` to out_ and returns %id.
  uint32_t emit(spv::Op op, uint32_t type, std::initializer_list<uint32_t> operands);
  uint32_t ext(uint32_t type, GLSLstd450 f, std::initializer_list<uint32_t> operands);

  void fuse(DeviceModelRewrite* counts);
  void perturb(DeviceModelRewrite* counts);
  // The perturbation sequences; each defines `result` from the driver's value `r`.
  uint32_t step(uint32_t t, int n, uint32_t r, uint32_t k, uint32_t result = 0);
  void fma_exact(uint32_t t, int n, uint32_t a, uint32_t b, uint32_t c, uint32_t result);
  void perturb_log(uint32_t t, int n, uint32_t r, uint32_t x, uint32_t result);
  uint32_t exp_steps(uint32_t t, int n, uint32_t x);
  uint32_t pow_steps(uint32_t t, int n, uint32_t x, uint32_t y);

  uint32_t header_[5] = {};
  uint32_t bound_ = 0;
  std::vector<Inst> head_;         // everything before the first OpFunction
  std::vector<Inst> added_;        // new types and constants, after head_
  std::vector<Inst> decorations_;  // new annotations, after the module's last one
  std::vector<Inst> body_;         // the functions
  std::vector<Inst> out_;          // the body being rewritten
  std::set<uint32_t> no_contraction_;
  std::map<uint32_t, uint32_t> renamed_;  // result id → the id its driver value now has

  std::unordered_map<uint32_t, std::pair<uint32_t, int>> vector_of_;  // type → (component, n)
  std::map<std::pair<uint32_t, int>, uint32_t> vector_type_;          // (component, n) → type
  uint32_t float32_ = 0, uint32_ = 0, bool_ = 0, glsl_ = 0;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> scalar_const_;  // (type, bits) → id
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> splat_const_;   // (type, scalar) → id
};

Status Rewriter::parse(const std::vector<uint32_t>& code) {
  if (code.size() < 5 || code[0] != spv::MagicNumber)
    return Error{"", "", "not a SPIR-V module (no magic number)", ""};
  std::memcpy(header_, code.data(), sizeof header_);
  bound_ = code[3];
  bool in_functions = false;
  for (size_t at = 5; at < code.size();) {
    const uint32_t words = code[at] >> 16;
    if (words == 0 || at + words > code.size())
      return Error{"", "word " + std::to_string(at), "SPIR-V instruction runs past the module", ""};
    Inst i;
    i.w.assign(code.begin() + static_cast<long>(at), code.begin() + static_cast<long>(at + words));
    at += words;
    if (i.op() == spv::OpFunction) in_functions = true;
    if (in_functions) {
      body_.push_back(std::move(i));
      continue;
    }
    switch (i.op()) {
      case spv::OpExtInstImport:
        if (literal_string(i, 2) == "GLSL.std.450") glsl_ = i.w[1];
        break;
      case spv::OpDecorate:
        if (i.w[2] == spv::DecorationNoContraction) no_contraction_.insert(i.w[1]);
        break;
      case spv::OpTypeFloat:
        if (i.w[2] == 32) float32_ = i.w[1];
        break;
      case spv::OpTypeInt:
        if (i.w[2] == 32 && i.w[3] == 0) uint32_ = i.w[1];
        break;
      case spv::OpTypeBool:
        bool_ = i.w[1];
        break;
      case spv::OpTypeVector:
        vector_of_[i.w[1]] = {i.w[2], static_cast<int>(i.w[3])};
        vector_type_[{i.w[2], static_cast<int>(i.w[3])}] = i.w[1];
        break;
      case spv::OpConstant:
        if (i.w.size() == 4) scalar_const_.emplace(std::pair{i.w[1], i.w[3]}, i.w[2]);
        break;
      case spv::OpConstantComposite: {
        bool same = i.w.size() > 4;
        for (size_t k = 4; k < i.w.size(); ++k) same = same && i.w[k] == i.w[3];
        if (same) splat_const_.emplace(std::pair{i.w[1], i.w[3]}, i.w[2]);
        break;
      }
      default:
        break;
    }
    head_.push_back(std::move(i));
  }
  return {};
}

int Rewriter::float32_components(uint32_t type) const {
  if (type == 0) return 0;
  if (type == float32_) return 1;
  auto it = vector_of_.find(type);
  if (it != vector_of_.end() && it->second.first == float32_) return it->second.second;
  return 0;
}

uint32_t Rewriter::type_uint(int n) {
  if (uint32_ == 0) {
    uint32_ = fresh();
    added_.push_back(make(spv::OpTypeInt, {uint32_, 32, 0}));
  }
  if (n == 1) return uint32_;
  auto [it, fresh_type] = vector_type_.try_emplace({uint32_, n}, 0);
  if (fresh_type) {
    it->second = fresh();
    vector_of_[it->second] = {uint32_, n};
    added_.push_back(make(spv::OpTypeVector, {it->second, uint32_, static_cast<uint32_t>(n)}));
  }
  return it->second;
}

uint32_t Rewriter::type_bool(int n) {
  if (bool_ == 0) {
    bool_ = fresh();
    added_.push_back(make(spv::OpTypeBool, {bool_}));
  }
  if (n == 1) return bool_;
  auto [it, fresh_type] = vector_type_.try_emplace({bool_, n}, 0);
  if (fresh_type) {
    it->second = fresh();
    vector_of_[it->second] = {bool_, n};
    added_.push_back(make(spv::OpTypeVector, {it->second, bool_, static_cast<uint32_t>(n)}));
  }
  return it->second;
}

// Only called for a component count some float32 type of the module has: both exist.
uint32_t Rewriter::type_float(int n) {
  return n == 1 ? float32_ : vector_type_.at({float32_, n});
}

uint32_t Rewriter::splat(uint32_t vector_type, uint32_t scalar, int n) {
  auto [it, fresh_const] = splat_const_.try_emplace({vector_type, scalar}, 0);
  if (fresh_const) {
    it->second = fresh();
    Inst c = make(spv::OpConstantComposite, {vector_type, it->second});
    for (int k = 0; k < n; ++k) c.w.push_back(scalar);
    c.w[0] = (static_cast<uint32_t>(c.w.size()) << 16) | spv::OpConstantComposite;
    added_.push_back(std::move(c));
  }
  return it->second;
}

uint32_t Rewriter::const_u(uint32_t value, int n) {
  const uint32_t t = type_uint(1);
  auto [it, fresh_const] = scalar_const_.try_emplace({t, value}, 0);
  if (fresh_const) {
    it->second = fresh();
    added_.push_back(make(spv::OpConstant, {t, it->second, value}));
  }
  return n == 1 ? it->second : splat(type_uint(n), it->second, n);
}

uint32_t Rewriter::const_f(float value, int n) {
  const uint32_t bits = std::bit_cast<uint32_t>(value);
  auto [it, fresh_const] = scalar_const_.try_emplace({float32_, bits}, 0);
  if (fresh_const) {
    it->second = fresh();
    added_.push_back(make(spv::OpConstant, {float32_, it->second, bits}));
  }
  return n == 1 ? it->second : splat(type_float(n), it->second, n);
}

// The GLSL.std.450 import, added after the module's other imports (before OpMemoryModel) if the
// module has none.
uint32_t Rewriter::glsl() {
  if (glsl_ != 0) return glsl_;
  glsl_ = fresh();
  // "GLSL.std.450" is 12 characters: three words, then a word holding the terminating nul.
  Inst imp = make(spv::OpExtInstImport, {glsl_});
  const char name[16] = "GLSL.std.450";
  for (int k = 0; k < 4; ++k) {
    uint32_t word = 0;
    std::memcpy(&word, name + 4 * k, 4);
    imp.w.push_back(word);
  }
  imp.w[0] = (static_cast<uint32_t>(imp.w.size()) << 16) | spv::OpExtInstImport;
  size_t at = 0;
  while (at < head_.size() &&
         (head_[at].op() == spv::OpCapability || head_[at].op() == spv::OpExtension ||
          head_[at].op() == spv::OpExtInstImport))
    ++at;
  head_.insert(head_.begin() + static_cast<long>(at), std::move(imp));
  return glsl_;
}

uint32_t Rewriter::emit(spv::Op op, uint32_t type, std::initializer_list<uint32_t> operands) {
  const uint32_t id = fresh();
  Inst i = make(op, {type, id});
  i.w.insert(i.w.end(), operands);
  i.w[0] = (static_cast<uint32_t>(i.w.size()) << 16) | static_cast<uint32_t>(op);
  out_.push_back(std::move(i));
  // The model's own arithmetic is evaluated as written: no driver may contract or rearrange it.
  if (op == spv::OpFAdd || op == spv::OpFSub || op == spv::OpFMul)
    decorations_.push_back(make(spv::OpDecorate, {id, spv::DecorationNoContraction}));
  return id;
}

uint32_t Rewriter::ext(uint32_t type, GLSLstd450 f, std::initializer_list<uint32_t> operands) {
  const uint32_t set = glsl();
  const uint32_t id = fresh();
  Inst i = make(spv::OpExtInst, {type, id, set, static_cast<uint32_t>(f)});
  i.w.insert(i.w.end(), operands);
  i.w[0] = (static_cast<uint32_t>(i.w.size()) << 16) | spv::OpExtInst;
  out_.push_back(std::move(i));
  return id;
}

// FMA fusion (Vulkan spec, "Precision and Operation of SPIR-V Instructions": without
// NoContraction, AllowContract is assumed: a·b + c may be evaluated with one rounding).
void Rewriter::fuse(DeviceModelRewrite* counts) {
  struct Mul {
    uint32_t type, a, b;
  };
  std::unordered_map<uint32_t, Mul> muls;
  for (const Inst& i : body_)
    if (i.op() == spv::OpFMul && float32_components(i.w[1]) > 0 && !no_contraction_.count(i.w[2]))
      muls[i.w[2]] = {i.w[1], i.w[3], i.w[4]};
  out_.clear();
  for (Inst& i : body_) {
    const bool add = i.op() == spv::OpFAdd, sub = i.op() == spv::OpFSub;
    if ((!add && !sub) || float32_components(i.w[1]) == 0 || no_contraction_.count(i.w[2])) {
      out_.push_back(std::move(i));
      continue;
    }
    const uint32_t type = i.w[1], result = i.w[2], lhs = i.w[3], rhs = i.w[4];
    auto mul_of = [&](uint32_t id) -> const Mul* {
      auto it = muls.find(id);
      return it != muls.end() && it->second.type == type ? &it->second : nullptr;
    };
    const Mul* m = mul_of(lhs);
    const bool mul_on_left = m != nullptr;
    if (!m) m = mul_of(rhs);
    if (!m) {
      out_.push_back(std::move(i));
      continue;
    }
    uint32_t x = m->a, y = m->b, z = mul_on_left ? rhs : lhs;
    if (sub && mul_on_left) z = emit(spv::OpFNegate, type, {z});   // a·b − c = fma(a, b, −c)
    if (sub && !mul_on_left) x = emit(spv::OpFNegate, type, {x});  // c − a·b = fma(−a, b, c)
    fma_exact(type, float32_components(type), x, y, z, result);
    ++counts->fused;
  }
  body_ = std::move(out_);
}

// a·b + c with one rounding, from float operations alone: lavapipe (Mesa's NIR) splits
// GLSL.std.450 Fma into a multiply and an add, so Fma itself would not show the freedom. Boldo and
// Melquiond, "Emulation of FMA and correctly rounded sums: proved algorithms using rounding to
// odd" (IEEE Trans. Computers 57(4), 2008), emulated FMA: (uh, ul) = ExactMult(a, b) (Dekker's
// product with Veltkamp's split by 2^12 + 1), (th, tl) = TwoSum(c, uh), v = RO(tl + ul), z =
// RN(th + v). Round-to-odd is RN(tl + ul) moved one step toward the exact sum when that sum is
// inexact (TwoSum's error ≠ 0) and the rounded value is even. Exact without underflow or
// overflow; where the split overflows or z is not finite, a·b + c unfused.
void Rewriter::fma_exact(uint32_t t, int n, uint32_t a, uint32_t b, uint32_t c, uint32_t result) {
  const uint32_t u = type_uint(n), bl = type_bool(n);
  auto f = [&](spv::Op op, uint32_t x, uint32_t y) { return emit(op, t, {x, y}); };
  auto split = [&](uint32_t x, uint32_t* hi, uint32_t* lo) {
    const uint32_t scaled = f(spv::OpFMul, const_f(4097.0f, n), x);
    *hi = f(spv::OpFSub, scaled, f(spv::OpFSub, scaled, x));
    *lo = f(spv::OpFSub, x, *hi);
  };
  uint32_t ah, al, bh, blo;
  split(a, &ah, &al);
  split(b, &bh, &blo);
  const uint32_t p = f(spv::OpFMul, a, b);
  uint32_t e = f(spv::OpFSub, f(spv::OpFMul, ah, bh), p);
  e = f(spv::OpFAdd, e, f(spv::OpFMul, ah, blo));
  e = f(spv::OpFAdd, e, f(spv::OpFMul, al, bh));
  e = f(spv::OpFAdd, e, f(spv::OpFMul, al, blo));  // p + e = a·b exactly
  // TwoSum(x, y) = (s, r): s = RN(x + y), s + r = x + y exactly.
  auto two_sum = [&](uint32_t x, uint32_t y, uint32_t* s, uint32_t* r) {
    *s = f(spv::OpFAdd, x, y);
    const uint32_t yy = f(spv::OpFSub, *s, x);
    const uint32_t xx = f(spv::OpFSub, *s, yy);
    *r = f(spv::OpFAdd, f(spv::OpFSub, x, xx), f(spv::OpFSub, y, yy));
  };
  uint32_t th, tl, v, verr;
  two_sum(c, p, &th, &tl);
  two_sum(tl, e, &v, &verr);
  const uint32_t vbits = emit(spv::OpBitcast, u, {v});
  const uint32_t low = emit(spv::OpBitwiseAnd, u, {vbits, const_u(1, n)});
  const uint32_t even = emit(spv::OpIEqual, bl, {low, const_u(0, n)});
  const uint32_t inexact = emit(spv::OpFOrdNotEqual, bl, {verr, const_f(0.0f, n)});
  const uint32_t to_odd = emit(spv::OpLogicalAnd, bl, {even, inexact});
  const uint32_t v_pos = emit(spv::OpFOrdGreaterThan, bl, {v, const_f(0.0f, n)});
  const uint32_t err_pos = emit(spv::OpFOrdGreaterThan, bl, {verr, const_f(0.0f, n)});
  const uint32_t outward = emit(spv::OpLogicalEqual, bl, {v_pos, err_pos});
  const uint32_t up = emit(spv::OpIAdd, u, {vbits, const_u(1, n)});
  const uint32_t down = emit(spv::OpISub, u, {vbits, const_u(1, n)});
  const uint32_t odd = emit(spv::OpSelect, u, {outward, up, down});
  const uint32_t ro = emit(spv::OpBitcast, t, {emit(spv::OpSelect, u, {to_odd, odd, vbits})});
  const uint32_t z = f(spv::OpFAdd, th, ro);
  const uint32_t unfused = f(spv::OpFAdd, p, c);
  const uint32_t nan = emit(spv::OpIsNan, bl, {z});
  const uint32_t inf = emit(spv::OpIsInf, bl, {z});
  const uint32_t bad = emit(spv::OpLogicalOr, bl, {nan, inf});
  out_.push_back(make(spv::OpSelect, {t, result, bad, unfused, z}));
}

// The driver's value `r` moved by `k` representable steps (uint, per component), toward or away
// from zero as perturb_away_from_zero says of its bits; away from zero falls back to toward zero
// at a power of two or where the move would leave the binade; NaN, Inf, 0 and |r| < 2^-125 (the
// exponent field below 2) stay. Defines `result` (fresh when 0).
uint32_t Rewriter::step(uint32_t t, int n, uint32_t r, uint32_t k, uint32_t result) {
  const uint32_t u = type_uint(n), b = type_bool(n);
  const uint32_t bits = emit(spv::OpBitcast, u, {r});
  const uint32_t mag = emit(spv::OpBitwiseAnd, u, {bits, const_u(0x7fffffffu, n)});
  const uint32_t sign = emit(spv::OpBitwiseAnd, u, {bits, const_u(0x80000000u, n)});
  const uint32_t exponent = emit(spv::OpShiftRightLogical, u, {mag, const_u(23, n)});
  const uint32_t hash = emit(spv::OpIMul, u, {bits, const_u(kPerturbHashMultiplier, n)});
  const uint32_t top = emit(spv::OpShiftRightLogical, u, {hash, const_u(31, n)});
  const uint32_t away = emit(spv::OpIEqual, b, {top, const_u(1, n)});
  const uint32_t mag_away = emit(spv::OpIAdd, u, {mag, k});
  const uint32_t exp_away = emit(spv::OpShiftRightLogical, u, {mag_away, const_u(23, n)});
  const uint32_t same_binade = emit(spv::OpIEqual, b, {exp_away, exponent});
  const uint32_t mantissa = emit(spv::OpBitwiseAnd, u, {mag, const_u(0x7fffffu, n)});
  const uint32_t not_pow2 = emit(spv::OpINotEqual, b, {mantissa, const_u(0, n)});
  const uint32_t can_away = emit(spv::OpLogicalAnd, b, {same_binade, not_pow2});
  const uint32_t go_away = emit(spv::OpLogicalAnd, b, {away, can_away});
  const uint32_t mag_toward = emit(spv::OpISub, u, {mag, k});
  const uint32_t moved_mag = emit(spv::OpSelect, u, {go_away, mag_away, mag_toward});
  const uint32_t moved = emit(spv::OpBitwiseOr, u, {sign, moved_mag});
  const uint32_t normal_lo = emit(spv::OpUGreaterThanEqual, b, {exponent, const_u(2, n)});
  const uint32_t normal_hi = emit(spv::OpULessThanEqual, b, {exponent, const_u(254, n)});
  const uint32_t movable = emit(spv::OpLogicalAnd, b, {normal_lo, normal_hi});
  const uint32_t chosen = emit(spv::OpSelect, u, {movable, moved, bits});
  if (result == 0) return emit(spv::OpBitcast, t, {chosen});
  out_.push_back(make(spv::OpBitcast, {t, result, chosen}));
  return result;
}

// log/log2: kLogSteps ULP outside [0.5, 2]; inside, ± kLogInsideShift (the sign from the same
// hash), except an exact 0 (x = 1).
void Rewriter::perturb_log(uint32_t t, int n, uint32_t r, uint32_t x, uint32_t result) {
  const uint32_t u = type_uint(n), b = type_bool(n);
  const uint32_t outside = step(t, n, r, const_u(kLogSteps, n));
  const uint32_t bits = emit(spv::OpBitcast, u, {r});
  const uint32_t hash = emit(spv::OpIMul, u, {bits, const_u(kPerturbHashMultiplier, n)});
  const uint32_t top = emit(spv::OpShiftRightLogical, u, {hash, const_u(31, n)});
  const uint32_t up = emit(spv::OpIEqual, b, {top, const_u(1, n)});
  const uint32_t shift =
      emit(spv::OpSelect, t, {up, const_f(kLogInsideShift, n), const_f(-kLogInsideShift, n)});
  const uint32_t shifted = emit(spv::OpFAdd, t, {r, shift});
  const uint32_t lo = emit(spv::OpFOrdGreaterThanEqual, b, {x, const_f(0.5f, n)});
  const uint32_t hi = emit(spv::OpFOrdLessThanEqual, b, {x, const_f(2.0f, n)});
  const uint32_t nonzero = emit(spv::OpFOrdNotEqual, b, {r, const_f(0.0f, n)});
  const uint32_t in_range = emit(spv::OpLogicalAnd, b, {lo, hi});
  const uint32_t inside = emit(spv::OpLogicalAnd, b, {in_range, nonzero});
  out_.push_back(make(spv::OpSelect, {t, result, inside, shifted, outside}));
}

// exp/exp2: floor(2.5 + 2|x|) = 2 + floor(2|x|) + (frac(2|x|) ≥ 0.5), every step exact in float
// (2|x| is exact, so are floor and the difference); 2|x| is capped at 4096 (any |x| ≥ 150 gives
// 0 or Inf, which stay).
uint32_t Rewriter::exp_steps(uint32_t t, int n, uint32_t x) {
  const uint32_t u = type_uint(n), b = type_bool(n);
  const uint32_t ax = ext(t, GLSLstd450FAbs, {x});
  const uint32_t twice = emit(spv::OpFMul, t, {ax, const_f(2.0f, n)});
  const uint32_t capped = ext(t, GLSLstd450FMin, {twice, const_f(4096.0f, n)});
  const uint32_t whole = ext(t, GLSLstd450Floor, {capped});
  const uint32_t frac = emit(spv::OpFSub, t, {capped, whole});
  const uint32_t half_up = emit(spv::OpFOrdGreaterThanEqual, b, {frac, const_f(0.5f, n)});
  const uint32_t whole_u = emit(spv::OpConvertFToU, u, {whole});
  const uint32_t base = emit(spv::OpSelect, u, {half_up, const_u(3, n), const_u(2, n)});
  return emit(spv::OpIAdd, u, {whole_u, base});
}

// pow: the steps of spirv_device_model.h (kPow*), from t = y·log2(x) as the driver computes it.
uint32_t Rewriter::pow_steps(uint32_t t, int n, uint32_t x, uint32_t y) {
  const uint32_t u = type_uint(n), b = type_bool(n);
  const uint32_t lx = ext(t, GLSLstd450Log2, {x});
  const uint32_t ty = emit(spv::OpFMul, t, {y, lx});
  const uint32_t at = ext(t, GLSLstd450FAbs, {ty});
  const uint32_t ay = ext(t, GLSLstd450FAbs, {y});
  const uint32_t lo = emit(spv::OpFOrdGreaterThanEqual, b, {x, const_f(0.5f, n)});
  const uint32_t hi = emit(spv::OpFOrdLessThanEqual, b, {x, const_f(2.0f, n)});
  const uint32_t inside = emit(spv::OpLogicalAnd, b, {lo, hi});
  const uint32_t coef_t = emit(spv::OpSelect, t,
                               {inside, const_f(static_cast<float>(kPowInsideT), n),
                                const_f(static_cast<float>(kPowOutsideT), n)});
  const uint32_t coef_y = emit(
      spv::OpSelect, t, {inside, const_f(static_cast<float>(kPowInsideY), n), const_f(0.0f, n)});
  const uint32_t term_t = emit(spv::OpFMul, t, {coef_t, at});
  const uint32_t term_y = emit(spv::OpFMul, t, {coef_y, ay});
  const uint32_t terms = emit(spv::OpFAdd, t, {term_t, term_y});
  const uint32_t steps = emit(spv::OpFAdd, t, {terms, const_f(2.5f, n)});
  const uint32_t capped =
      ext(t, GLSLstd450FMin, {steps, const_f(static_cast<float>(kMaxPowSteps), n)});
  const uint32_t whole = ext(t, GLSLstd450Floor, {capped});
  return emit(spv::OpConvertFToU, u, {whole});
}

void Rewriter::perturb(DeviceModelRewrite* counts) {
  out_.clear();
  for (Inst& i : body_) {
    const spv::Op op = i.op();
    const bool div = op == spv::OpFDiv;
    const bool ext_inst = op == spv::OpExtInst && glsl_ != 0 && i.w[3] == glsl_;
    const uint32_t f = ext_inst ? i.w[4] : 0;
    const bool transcendental =
        ext_inst && (f == GLSLstd450Exp2 || f == GLSLstd450Exp || f == GLSLstd450Log2 ||
                     f == GLSLstd450Log || f == GLSLstd450Pow);
    const int n = (div || transcendental) ? float32_components(i.w[1]) : 0;
    if (n == 0) {
      out_.push_back(std::move(i));
      continue;
    }
    // The driver's value gets a new id; the original id is defined by the moved value, so every
    // use (and decoration) of the result sees the worst-case device's.
    const uint32_t t = i.w[1], result = i.w[2], r = fresh();
    renamed_[result] = r;
    i.w[2] = r;
    const uint32_t x = div ? 0 : i.w[5];
    const uint32_t y = f == GLSLstd450Pow ? i.w[6] : 0;
    out_.push_back(std::move(i));
    if (div) {
      step(t, n, r, const_u(kDivisionSteps, n), result);
      ++counts->divisions;
    } else if (f == GLSLstd450Exp2 || f == GLSLstd450Exp) {
      step(t, n, r, exp_steps(t, n, x), result);
      ++(f == GLSLstd450Exp2 ? counts->exp2 : counts->exp);
    } else if (f == GLSLstd450Log2 || f == GLSLstd450Log) {
      perturb_log(t, n, r, x, result);
      ++(f == GLSLstd450Log2 ? counts->log2 : counts->log);
    } else {
      step(t, n, r, pow_steps(t, n, x, y), result);
      ++counts->pow;
    }
  }
  body_ = std::move(out_);
  // Decorations of a moved result (NoContraction, RelaxedPrecision) stay on the driver's
  // operation, the one they describe.
  for (Inst& i : head_)
    if ((i.op() == spv::OpDecorate || i.op() == spv::OpDecorateId) && renamed_.count(i.w[1]))
      i.w[1] = renamed_.at(i.w[1]);
}

DeviceModelRewrite Rewriter::run() {
  DeviceModelRewrite counts;
  fuse(&counts);
  perturb(&counts);
  return counts;
}

std::vector<uint32_t> Rewriter::assemble() const {
  // Annotations go after the module's last one (SPIR-V spec, 2.4 "Logical Layout of a Module"),
  // else before its first type.
  auto annotation = [](spv::Op op) {
    return op == spv::OpDecorate || op == spv::OpMemberDecorate || op == spv::OpDecorateId ||
           op == spv::OpDecorationGroup || op == spv::OpGroupDecorate ||
           op == spv::OpGroupMemberDecorate || op == spv::OpDecorateString ||
           op == spv::OpMemberDecorateString;
  };
  size_t at = head_.size();
  for (size_t k = head_.size(); k-- > 0;)
    if (annotation(head_[k].op())) {
      at = k + 1;
      break;
    }
  if (at == head_.size())
    for (size_t k = 0; k < head_.size(); ++k)
      if (head_[k].op() >= spv::OpTypeVoid && head_[k].op() <= spv::OpTypeForwardPointer) {
        at = k;
        break;
      }
  std::vector<uint32_t> code(header_, header_ + 5);
  code[3] = bound_;
  auto put = [&code](const Inst& i) { code.insert(code.end(), i.w.begin(), i.w.end()); };
  for (size_t k = 0; k < head_.size(); ++k) {
    if (k == at)
      for (const Inst& d : decorations_) put(d);
    put(head_[k]);
  }
  if (at == head_.size())
    for (const Inst& d : decorations_) put(d);
  for (const auto* part : {&added_, &body_})
    for (const Inst& i : *part) put(i);
  return code;
}

}  // namespace

Result<DeviceModelRewrite> apply_worst_device_model(std::vector<uint32_t>* spirv) {
  Rewriter rw;
  if (Status s = rw.parse(*spirv); !s) return s.error();
  DeviceModelRewrite counts = rw.run();
  *spirv = rw.assemble();
  return counts;
}

std::string worst_device_glsl_preamble() {
  const std::string bits = std::to_string(kWorstModelSubTexelBits);
  // Vulkan spec, "Texel Filtering" (linear filtering, "Texel Coordinate Systems", clamp to edge):
  // u = s·width − 0.5, i0 = ⌊u⌋, i1 = i0 + 1, α = frac(u), each index clamped to [0, size − 1];
  // τ = Σ of the corner texels times the products of (1 − α) or α per axis. α truncated to `bits`
  // fractional bits (ldexp: exact, and no division for the rewrite to perturb); `precise` keeps
  // the filter's own arithmetic unfused, as the specification's formula writes it. The level is
  // 0: the engine's samplers have maxLod 0 and every lookup passes 0.0.
  return R"(#define HDRC_DEVICE_MODEL_WORST 1
float hdrc_filter_weight(float a, int bits) {
  return bits < 0 ? a : ldexp(floor(ldexp(a, bits)), -bits);
}
vec4 hdrc_filter_lod(sampler2D s, vec2 c, float lod, int bits) {
  ivec2 size = textureSize(s, 0);
  precise vec2 u = c * vec2(size) - 0.5;
  vec2 i0f = floor(u);
  precise vec2 f = u - i0f;
  vec2 a = vec2(hdrc_filter_weight(f.x, bits), hdrc_filter_weight(f.y, bits));
  ivec2 i0 = clamp(ivec2(i0f), ivec2(0), size - 1);
  ivec2 i1 = clamp(ivec2(i0f) + 1, ivec2(0), size - 1);
  vec4 t00 = texelFetch(s, ivec2(i0.x, i0.y), 0), t10 = texelFetch(s, ivec2(i1.x, i0.y), 0);
  vec4 t01 = texelFetch(s, ivec2(i0.x, i1.y), 0), t11 = texelFetch(s, ivec2(i1.x, i1.y), 0);
  precise vec2 b = 1.0 - a;
  precise vec4 v = b.x * b.y * t00 + a.x * b.y * t10 + b.x * a.y * t01 + a.x * a.y * t11;
  return v;
}
vec4 hdrc_filter_lod(sampler3D s, vec3 c, float lod, int bits) {
  ivec3 size = textureSize(s, 0);
  precise vec3 u = c * vec3(size) - 0.5;
  vec3 i0f = floor(u);
  precise vec3 f = u - i0f;
  vec3 a = vec3(hdrc_filter_weight(f.x, bits), hdrc_filter_weight(f.y, bits),
                hdrc_filter_weight(f.z, bits));
  ivec3 i0 = clamp(ivec3(i0f), ivec3(0), size - 1);
  ivec3 i1 = clamp(ivec3(i0f) + 1, ivec3(0), size - 1);
  precise vec3 b = 1.0 - a;
  precise vec4 v =
      b.x * b.y * b.z * texelFetch(s, ivec3(i0.x, i0.y, i0.z), 0) +
      a.x * b.y * b.z * texelFetch(s, ivec3(i1.x, i0.y, i0.z), 0) +
      b.x * a.y * b.z * texelFetch(s, ivec3(i0.x, i1.y, i0.z), 0) +
      a.x * a.y * b.z * texelFetch(s, ivec3(i1.x, i1.y, i0.z), 0) +
      b.x * b.y * a.z * texelFetch(s, ivec3(i0.x, i0.y, i1.z), 0) +
      a.x * b.y * a.z * texelFetch(s, ivec3(i1.x, i0.y, i1.z), 0) +
      b.x * a.y * a.z * texelFetch(s, ivec3(i0.x, i1.y, i1.z), 0) +
      a.x * a.y * a.z * texelFetch(s, ivec3(i1.x, i1.y, i1.z), 0);
  return v;
}
#define textureLod(s, c, l) hdrc_filter_lod(s, c, l, )" +
         bits + ")\n";
}

}  // namespace hdrc::gpu
