// What the GPU's shaders share (put before step.wgsl and contact.wgsl): the largest f64, a
// test of finiteness, and f64 exp, ln and pow.

const BIG: f64 = 1.7976931348623157e308lf;

// x is finite (neither infinite nor NaN: a NaN compares false).
fn finite(x: f64) -> bool {
    return abs(x) <= BIG;
}

// ---------------------------------------------------------------- f64 exp, ln, pow
// Vulkan has no 64-bit exp, log or pow (GLSL.std.450 takes 16- and 32-bit floats only), so
// they are written out here, to a few units in the last place (the CPU uses libm: the two
// agree to round-off, well inside the tests' 1e-10).

const LN2_HI: f64 = 6.93147180369123816490e-01lf;
const LN2_LO: f64 = 1.90821492927058770002e-10lf;

// 2^k, exactly: the binary powers of 2 (or 1/2) multiplied up (powers of two multiply
// without rounding).
fn pow2(k: i32) -> f64 {
    var b = 2.0lf;
    if (k < 0) {
        b = 0.5lf;
    }
    var n = abs(k);
    var r = 1.0lf;
    while (n > 0) {
        if ((n & 1) != 0) {
            r = r * b;
        }
        b = b * b;
        n = n >> 1u;
    }
    return r;
}

// e^x: x = k ln 2 + r, |r| <= ln 2 / 2, e^r by its Taylor series to r^17/17! (< 2e-19
// relative), times 2^k.
fn exp64(x: f64) -> f64 {
    if (x > 709.0lf) {
        return BIG * 2.0lf;
    }
    if (x < -745.0lf) {
        return 0.0lf;
    }
    let k = round(x * 1.4426950408889634lf);
    let r = (x - k * LN2_HI) - k * LN2_LO;
    var term = 1.0lf;
    var sum = 1.0lf;
    for (var i = 1; i <= 17; i = i + 1) {
        term = term * r / f64(i);
        sum = sum + term;
    }
    return sum * pow2(i32(k));
}

// ln x for x > 0: x = m 2^e with m in [1/sqrt 2, sqrt 2) (e first guessed in f32, then
// made exact), ln m = 2 atanh(s), s = (m-1)/(m+1), |s| < 0.172, by its series to s^29
// (< 1e-22); ln 0 = -inf, ln of a negative number NaN.
fn ln64(x: f64) -> f64 {
    if (x <= 0.0lf) {
        if (x == 0.0lf) {
            return -BIG * 2.0lf;
        }
        return (x - x) / (x - x);
    }
    if (x > BIG) {
        return x;
    }
    var y = x;
    var e = 0;
    while (y > 1e30lf) {
        y = y * 7.888609052210118e-31lf;
        e = e + 100;
    }
    while (y < 1e-30lf) {
        y = y * 1.2676506002282294e30lf;
        e = e - 100;
    }
    let k = i32(floor(log2(f32(y))));
    var m = y * pow2(-k);
    e = e + k;
    while (m >= 2.0lf) {
        m = m * 0.5lf;
        e = e + 1;
    }
    while (m < 1.0lf) {
        m = m * 2.0lf;
        e = e - 1;
    }
    if (m > 1.4142135623730951lf) {
        m = m * 0.5lf;
        e = e + 1;
    }
    let t = (m - 1.0lf) / (m + 1.0lf);
    let t2 = t * t;
    var sum = 0.0lf;
    for (var i = 29; i >= 1; i = i - 2) {
        sum = sum * t2 + 1.0lf / f64(i);
    }
    return f64(e) * LN2_HI + (f64(e) * LN2_LO + 2.0lf * t * sum);
}

// x^y for x > 0 (0 for x = 0 and y > 0).
fn pow64(x: f64, y: f64) -> f64 {
    if (x == 0.0lf) {
        return 0.0lf;
    }
    return exp64(y * ln64(x));
}
