//! Arithmetic of `*PARAMETER_EXPRESSION`: numbers, parameter names (with or without their
//! `&`), `+ - * /`, powers `**` or `^` (right-associative, above unary minus as in Fortran:
//! `-2**2` is -4), parentheses, the constant `pi` and the functions
//! `sin cos tan asin acos atan atan2 sinh cosh tanh sqrt exp log ln log10 abs sign min max
//! pow int nint mod`. Names and functions are case-insensitive.

/// Evaluates `text`, looking names up with `lookup` (None: undefined).
pub fn eval(text: &str, lookup: &dyn Fn(&str) -> Option<f64>) -> Result<f64, String> {
    let mut p = Parser {
        s: text.as_bytes(),
        i: 0,
        depth: 0,
        lookup,
    };
    let v = p.expr()?;
    p.skip();
    if p.i < p.s.len() {
        return Err(format!(
            "unexpected '{}' at column {} of '{text}'",
            p.s[p.i] as char,
            p.i + 1
        ));
    }
    if !v.is_finite() {
        return Err(format!("'{text}' is not a finite number ({v})"));
    }
    Ok(v)
}

/// How deeply parentheses, signs and powers may nest (a bound on the recursion).
const MAX_DEPTH: usize = 200;

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
    depth: usize,
    lookup: &'a dyn Fn(&str) -> Option<f64>,
}

impl Parser<'_> {
    fn skip(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip();
        self.s.get(self.i).copied()
    }

    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.i += 1;
            true
        } else {
            false
        }
    }

    fn expr(&mut self) -> Result<f64, String> {
        let mut v = self.term()?;
        loop {
            if self.eat(b'+') {
                v += self.term()?;
            } else if self.eat(b'-') {
                v -= self.term()?;
            } else {
                return Ok(v);
            }
        }
    }

    fn term(&mut self) -> Result<f64, String> {
        let mut v = self.unary()?;
        loop {
            if self.peek() == Some(b'*') && self.s.get(self.i + 1) != Some(&b'*') {
                self.i += 1;
                v *= self.unary()?;
            } else if self.eat(b'/') {
                v /= self.unary()?;
            } else {
                return Ok(v);
            }
        }
    }

    fn unary(&mut self) -> Result<f64, String> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(format!("nested deeper than {MAX_DEPTH} levels"));
        }
        let v = if self.eat(b'-') {
            self.unary().map(|v| -v)
        } else if self.eat(b'+') {
            self.unary()
        } else {
            self.power()
        };
        self.depth -= 1;
        v
    }

    fn power(&mut self) -> Result<f64, String> {
        let base = self.primary()?;
        let pow = if self.peek() == Some(b'*') && self.s.get(self.i + 1) == Some(&b'*') {
            self.i += 2;
            true
        } else {
            self.eat(b'^')
        };
        if pow {
            let e = self.unary()?;
            return Ok(base.powf(e));
        }
        Ok(base)
    }

    fn primary(&mut self) -> Result<f64, String> {
        match self.peek() {
            None => Err("the expression ends too early".into()),
            Some(b'(') => {
                self.i += 1;
                let v = self.expr()?;
                if !self.eat(b')') {
                    return Err("a ')' is missing".into());
                }
                Ok(v)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() || c == b'_' || c == b'&' => self.name(),
            Some(c) => Err(format!("unexpected '{}'", c as char)),
        }
    }

    fn number(&mut self) -> Result<f64, String> {
        let start = self.i;
        while self.i < self.s.len() {
            let c = self.s[self.i];
            let exp_sign = (c == b'+' || c == b'-')
                && self.i > start
                && matches!(self.s[self.i - 1], b'e' | b'E' | b'd' | b'D');
            if c.is_ascii_digit() || c == b'.' || matches!(c, b'e' | b'E' | b'd' | b'D') || exp_sign
            {
                self.i += 1;
            } else {
                break;
            }
        }
        let t = std::str::from_utf8(&self.s[start..self.i]).unwrap_or("");
        t.replace(['d', 'D'], "e")
            .parse()
            .map_err(|_| format!("'{t}' is not a number"))
    }

    fn name(&mut self) -> Result<f64, String> {
        self.eat(b'&');
        let start = self.i;
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_')
        {
            self.i += 1;
        }
        let name = std::str::from_utf8(&self.s[start..self.i])
            .unwrap_or("")
            .to_ascii_lowercase();
        if self.eat(b'(') {
            let mut args = vec![self.expr()?];
            while self.eat(b',') {
                args.push(self.expr()?);
            }
            if !self.eat(b')') {
                return Err(format!("a ')' is missing after the arguments of {name}"));
            }
            return call(&name, &args);
        }
        if name == "pi" {
            return Ok(std::f64::consts::PI);
        }
        (self.lookup)(&name).ok_or_else(|| format!("parameter '{name}' is not defined"))
    }
}

fn call(name: &str, a: &[f64]) -> Result<f64, String> {
    let one = |f: fn(f64) -> f64| {
        if a.len() == 1 {
            Ok(f(a[0]))
        } else {
            Err(format!("{name} takes one argument, not {}", a.len()))
        }
    };
    let two = |f: fn(f64, f64) -> f64| {
        if a.len() == 2 {
            Ok(f(a[0], a[1]))
        } else {
            Err(format!("{name} takes two arguments, not {}", a.len()))
        }
    };
    match name {
        "sin" => one(f64::sin),
        "cos" => one(f64::cos),
        "tan" => one(f64::tan),
        "asin" => one(f64::asin),
        "acos" => one(f64::acos),
        "atan" => one(f64::atan),
        "atan2" => two(f64::atan2),
        "sinh" => one(f64::sinh),
        "cosh" => one(f64::cosh),
        "tanh" => one(f64::tanh),
        "sqrt" => one(f64::sqrt),
        "exp" => one(f64::exp),
        "log" | "ln" => one(f64::ln),
        "log10" => one(f64::log10),
        "abs" => one(f64::abs),
        "sign" => one(f64::signum),
        "int" | "aint" => one(f64::trunc),
        "nint" => one(f64::round),
        "pow" => two(f64::powf),
        "mod" => two(|x, y| x % y),
        "min" | "max" if !a.is_empty() => {
            Ok(a.iter()
                .copied()
                .fold(a[0], |m, x| if name == "min" { m.min(x) } else { m.max(x) }))
        }
        _ => Err(format!("unknown function '{name}'")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(t: &str) -> Result<f64, String> {
        eval(t, &|n| match n {
            "rho" => Some(7850.0),
            "v0" => Some(-2.5),
            _ => None,
        })
    }

    #[test]
    fn arithmetic_precedence_and_functions() {
        assert_eq!(ev("1 + 2 * 3").unwrap(), 7.0);
        assert_eq!(ev("(1 + 2) * 3").unwrap(), 9.0);
        assert_eq!(ev("2**3**2").unwrap(), 512.0);
        assert_eq!(ev("-2**2").unwrap(), -4.0);
        assert_eq!(ev("2^-1").unwrap(), 0.5);
        assert_eq!(ev("8 / 4 / 2").unwrap(), 1.0);
        assert_eq!(ev("1.5d3 + 1e-3*1000").unwrap(), 1501.0);
        assert_eq!(ev("rho*2").unwrap(), 15700.0);
        assert_eq!(ev("&V0 * -2").unwrap(), 5.0);
        assert!((ev("sqrt(2)*cos(pi/4)").unwrap() - 1.0).abs() < 1e-15);
        assert_eq!(ev("max(1, rho, 3)").unwrap(), 7850.0);
        assert_eq!(ev("atan2(0, -1)").unwrap(), std::f64::consts::PI);
    }

    #[test]
    fn errors_say_what() {
        assert!(ev("x + 1").unwrap_err().contains("'x' is not defined"));
        assert!(ev("(1 + 2").unwrap_err().contains("')'"));
        assert!(ev("1 + ").unwrap_err().contains("ends too early"));
        assert!(ev("foo(1)").unwrap_err().contains("unknown function"));
        assert!(ev("1 / 0").unwrap_err().contains("not a finite"));
        assert!(ev("2 3").unwrap_err().contains("unexpected '3'"));
        assert!(ev("sqrt(1, 2)").unwrap_err().contains("one argument"));
        let deep = format!("{}1{}", "(".repeat(100_000), ")".repeat(100_000));
        assert!(ev(&deep).unwrap_err().contains("nested deeper"));
        assert!(ev(&"-".repeat(100_000))
            .unwrap_err()
            .contains("nested deeper"));
    }
}
