//! Arithmetic in `${…}`: numbers, parameter names, `+ − * / ^` (or `**`), parentheses,
//! `pi`, and the functions `sqrt abs exp ln log10 sin cos tan asin acos atan floor ceil round
//! min max`. Everything is an `f64`: `${1/2}` is 0.5 (a general-purpose expression crate with
//! integer division would make it 0, a trap in physical input).

/// The functions an expression may call, with their argument counts (`None`: one or more).
const FUNCTIONS: [(&str, Option<usize>); 15] = [
    ("sqrt", Some(1)),
    ("abs", Some(1)),
    ("exp", Some(1)),
    ("ln", Some(1)),
    ("log10", Some(1)),
    ("sin", Some(1)),
    ("cos", Some(1)),
    ("tan", Some(1)),
    ("asin", Some(1)),
    ("acos", Some(1)),
    ("atan", Some(1)),
    ("floor", Some(1)),
    ("ceil", Some(1)),
    ("round", Some(1)),
    ("min", None),
];

/// Names an expression reserves (functions and constants); a parameter may not take them.
pub(crate) fn is_reserved(name: &str) -> bool {
    name == "pi" || name == "max" || FUNCTIONS.iter().any(|f| f.0 == name)
}

/// Whether `name` can be a parameter: a letter or `_`, then letters, digits or `_`.
pub(crate) fn is_identifier(name: &str) -> bool {
    let mut c = name.chars();
    c.next()
        .is_some_and(|f| f.is_ascii_alphabetic() || f == '_')
        && c.all(|x| x.is_ascii_alphanumeric() || x == '_')
}

/// Evaluates `text`, looking names up with `lookup` (`Err` with the reason for a name that
/// is not a number).
pub(crate) fn evaluate(
    text: &str,
    lookup: &mut dyn FnMut(&str) -> Result<f64, String>,
) -> Result<f64, String> {
    let mut p = Parser {
        s: text.as_bytes(),
        at: 0,
        lookup,
    };
    let v = p.sum()?;
    p.skip_spaces();
    if p.at < p.s.len() {
        return Err(format!(
            "unexpected `{}` at character {}",
            &text[p.at..],
            p.at + 1
        ));
    }
    Ok(v)
}

struct Parser<'a, 'b> {
    s: &'a [u8],
    at: usize,
    lookup: &'b mut dyn FnMut(&str) -> Result<f64, String>,
}

impl Parser<'_, '_> {
    fn skip_spaces(&mut self) {
        while self.at < self.s.len() && self.s[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip_spaces();
        self.s.get(self.at).copied()
    }

    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.at += 1;
            true
        } else {
            false
        }
    }

    /// `term (('+' | '-') term)*`
    fn sum(&mut self) -> Result<f64, String> {
        let mut v = self.product()?;
        loop {
            if self.eat(b'+') {
                v += self.product()?;
            } else if self.eat(b'-') {
                v -= self.product()?;
            } else {
                return Ok(v);
            }
        }
    }

    /// `unary (('*' | '/') unary)*`
    fn product(&mut self) -> Result<f64, String> {
        let mut v = self.unary()?;
        loop {
            if self.peek() == Some(b'*') && self.s.get(self.at + 1) != Some(&b'*') {
                self.at += 1;
                v *= self.unary()?;
            } else if self.eat(b'/') {
                v /= self.unary()?;
            } else {
                return Ok(v);
            }
        }
    }

    /// `('-' | '+') unary | power`
    fn unary(&mut self) -> Result<f64, String> {
        if self.eat(b'-') {
            Ok(-self.unary()?)
        } else if self.eat(b'+') {
            self.unary()
        } else {
            self.power()
        }
    }

    /// `atom (('^' | '**') unary)?`, right-associative.
    fn power(&mut self) -> Result<f64, String> {
        let base = self.atom()?;
        if self.eat(b'^') {
            return Ok(base.powf(self.unary()?));
        }
        if self.peek() == Some(b'*') && self.s.get(self.at + 1) == Some(&b'*') {
            self.at += 2;
            return Ok(base.powf(self.unary()?));
        }
        Ok(base)
    }

    /// A number, a name, a call or a parenthesised sum.
    fn atom(&mut self) -> Result<f64, String> {
        match self.peek() {
            None => Err("the expression ends too early".into()),
            Some(b'(') => {
                self.at += 1;
                let v = self.sum()?;
                if !self.eat(b')') {
                    return Err("a `(` without its `)`".into());
                }
                Ok(v)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => {
                let start = self.at;
                while self.at < self.s.len()
                    && (self.s[self.at].is_ascii_alphanumeric() || self.s[self.at] == b'_')
                {
                    self.at += 1;
                }
                let name = std::str::from_utf8(&self.s[start..self.at]).expect("ASCII");
                if self.eat(b'(') {
                    return self.call(name);
                }
                if name == "pi" {
                    return Ok(std::f64::consts::PI);
                }
                (self.lookup)(name)
            }
            Some(c) => Err(format!("unexpected `{}`", c as char)),
        }
    }

    fn number(&mut self) -> Result<f64, String> {
        let start = self.at;
        let digits = |p: &mut Self| {
            while p.at < p.s.len() && (p.s[p.at].is_ascii_digit() || p.s[p.at] == b'.') {
                p.at += 1;
            }
        };
        digits(self);
        if self.at < self.s.len() && matches!(self.s[self.at], b'e' | b'E') {
            let mark = self.at;
            self.at += 1;
            if self.at < self.s.len() && matches!(self.s[self.at], b'+' | b'-') {
                self.at += 1;
            }
            if self.at < self.s.len() && self.s[self.at].is_ascii_digit() {
                digits(self);
            } else {
                self.at = mark;
            }
        }
        let text = std::str::from_utf8(&self.s[start..self.at]).expect("ASCII");
        text.parse::<f64>()
            .map_err(|_| format!("`{text}` is not a number"))
    }

    /// The arguments of `name(…)` (after the `(`) and the call.
    fn call(&mut self, name: &str) -> Result<f64, String> {
        let mut args = Vec::new();
        if !self.eat(b')') {
            loop {
                args.push(self.sum()?);
                if self.eat(b')') {
                    break;
                }
                if !self.eat(b',') {
                    return Err(format!("`{name}(`: expected `,` or `)`"));
                }
            }
        }
        let arity = match FUNCTIONS.iter().find(|f| f.0 == name) {
            Some(f) => f.1,
            None if name == "max" => None,
            None => {
                return Err(format!(
                    "unknown function `{name}`; the functions: {}, max",
                    FUNCTIONS.map(|f| f.0).join(", ")
                ))
            }
        };
        match arity {
            Some(n) if args.len() != n => {
                return Err(format!("`{name}` takes {n} argument, {} given", args.len()))
            }
            None if args.is_empty() => return Err(format!("`{name}` takes at least 1 argument")),
            _ => {}
        }
        let x = args[0];
        Ok(match name {
            "sqrt" => x.sqrt(),
            "abs" => x.abs(),
            "exp" => x.exp(),
            "ln" => x.ln(),
            "log10" => x.log10(),
            "sin" => x.sin(),
            "cos" => x.cos(),
            "tan" => x.tan(),
            "asin" => x.asin(),
            "acos" => x.acos(),
            "atan" => x.atan(),
            "floor" => x.floor(),
            "ceil" => x.ceil(),
            "round" => x.round(),
            "min" => args.iter().copied().fold(f64::INFINITY, f64::min),
            _ => args.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(s: &str) -> Result<f64, String> {
        evaluate(s, &mut |n| match n {
            "H" => Ok(0.01),
            "n" => Ok(4.0),
            other => Err(format!("unknown parameter `{other}`")),
        })
    }

    #[test]
    fn arithmetic_follows_the_usual_precedence_in_floating_point() {
        assert_eq!(eval("1/2").unwrap(), 0.5);
        assert_eq!(eval("H / 20").unwrap(), 0.01 / 20.0);
        assert_eq!(eval("2 + 3 * 4").unwrap(), 14.0);
        assert_eq!(eval("(2 + 3) * 4").unwrap(), 20.0);
        assert_eq!(eval("-2^2").unwrap(), -4.0);
        assert_eq!(eval("2^3^2").unwrap(), 512.0);
        assert_eq!(eval("2**n").unwrap(), 16.0);
        assert_eq!(eval("1.5e-3 * 2").unwrap(), 3e-3);
        assert_eq!(eval("sqrt(n) + max(1, n, 2) - min(3, 1)").unwrap(), 5.0);
        assert_eq!(eval("2*pi").unwrap(), 2.0 * std::f64::consts::PI);
    }

    #[test]
    fn mistakes_are_named() {
        assert!(eval("H / W").unwrap_err().contains("unknown parameter `W`"));
        assert!(eval("2 +").unwrap_err().contains("ends too early"));
        assert!(eval("(2").unwrap_err().contains("`(` without"));
        assert!(eval("2 3").unwrap_err().contains("unexpected `3`"));
        assert!(eval("cosh(1)")
            .unwrap_err()
            .contains("unknown function `cosh`"));
        assert!(eval("sqrt(1, 2)").unwrap_err().contains("takes 1 argument"));
        assert!(is_identifier("dp_1") && !is_identifier("1dp") && !is_identifier("a-b"));
        assert!(is_reserved("sqrt") && is_reserved("pi") && !is_reserved("H"));
    }
}
