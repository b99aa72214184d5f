//! Analytical references: arithmetic with `+ - * / ^`, parentheses, the
//! functions sin, cos, tan, asin, acos, atan, sqrt, exp, ln, abs and
//! rad (degrees to radians), the constant pi, and variables: the swept
//! fields by their paths (`default_joint.friction_angle`) and the figure's
//! time `t`.

/// Evaluates `text` with `var` giving the variables' values.
pub fn eval(text: &str, var: &dyn Fn(&str) -> Option<f64>) -> Result<f64, String> {
    let mut p = Expr {
        s: text.as_bytes(),
        at: 0,
        var,
    };
    let v = p.sum()?;
    p.blank();
    if p.at < p.s.len() {
        return Err(p.wanted("an operator or the end"));
    }
    Ok(v)
}

struct Expr<'a> {
    s: &'a [u8],
    at: usize,
    var: &'a dyn Fn(&str) -> Option<f64>,
}

impl Expr<'_> {
    fn blank(&mut self) {
        while self.s.get(self.at).is_some_and(u8::is_ascii_whitespace) {
            self.at += 1;
        }
    }

    fn eat(&mut self, c: u8) -> bool {
        self.blank();
        if self.s.get(self.at) == Some(&c) {
            self.at += 1;
            true
        } else {
            false
        }
    }

    fn wanted(&self, what: &str) -> String {
        format!(
            "expected {what} at character {} of `{}`",
            self.at + 1,
            String::from_utf8_lossy(self.s)
        )
    }

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

    fn product(&mut self) -> Result<f64, String> {
        let mut v = self.unary()?;
        loop {
            if self.eat(b'*') {
                v *= self.unary()?;
            } else if self.eat(b'/') {
                v /= self.unary()?;
            } else {
                return Ok(v);
            }
        }
    }

    fn unary(&mut self) -> Result<f64, String> {
        if self.eat(b'-') {
            return Ok(-self.unary()?);
        }
        if self.eat(b'+') {
            return self.unary();
        }
        let base = self.atom()?;
        if self.eat(b'^') {
            // Right associative, binding tighter than a leading minus.
            return Ok(base.powf(self.unary()?));
        }
        Ok(base)
    }

    fn atom(&mut self) -> Result<f64, String> {
        self.blank();
        if self.eat(b'(') {
            let v = self.sum()?;
            if !self.eat(b')') {
                return Err(self.wanted("`)`"));
            }
            return Ok(v);
        }
        let start = self.at;
        let c = *self.s.get(self.at).ok_or_else(|| self.wanted("a value"))?;
        if c.is_ascii_digit() || c == b'.' {
            while self
                .s
                .get(self.at)
                .is_some_and(|c| c.is_ascii_digit() || *c == b'.')
            {
                self.at += 1;
            }
            if self
                .s
                .get(self.at)
                .is_some_and(|c| *c == b'e' || *c == b'E')
            {
                self.at += 1;
                if self
                    .s
                    .get(self.at)
                    .is_some_and(|c| *c == b'-' || *c == b'+')
                {
                    self.at += 1;
                }
                while self.s.get(self.at).is_some_and(u8::is_ascii_digit) {
                    self.at += 1;
                }
            }
            let text = std::str::from_utf8(&self.s[start..self.at]).unwrap_or("");
            return text.parse().map_err(|_| self.wanted("a number"));
        }
        if !(c.is_ascii_alphabetic() || c == b'_') {
            return Err(self.wanted("a number, a name or `(`"));
        }
        while self
            .s
            .get(self.at)
            .is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_' || *c == b'.')
        {
            self.at += 1;
        }
        let name = String::from_utf8_lossy(&self.s[start..self.at]).into_owned();
        if self.eat(b'(') {
            let x = self.sum()?;
            if !self.eat(b')') {
                return Err(self.wanted("`)`"));
            }
            let f: fn(f64) -> f64 = match name.as_str() {
                "sin" => f64::sin,
                "cos" => f64::cos,
                "tan" => f64::tan,
                "asin" => f64::asin,
                "acos" => f64::acos,
                "atan" => f64::atan,
                "sqrt" => f64::sqrt,
                "exp" => f64::exp,
                "ln" => f64::ln,
                "abs" => f64::abs,
                "rad" => f64::to_radians,
                _ => {
                    return Err(format!(
                        "unknown function `{name}`: known are sin, cos, tan, asin, acos, atan, sqrt, exp, ln, abs, rad"
                    ))
                }
            };
            return Ok(f(x));
        }
        if name == "pi" {
            return Ok(std::f64::consts::PI);
        }
        (self.var)(&name)
            .ok_or_else(|| format!("unknown name `{name}`: use pi, t or a swept field's path"))
    }
}

#[cfg(test)]
mod tests {
    use super::eval;

    #[test]
    fn sliding_block_and_names() {
        let var = |n: &str| match n {
            "t" => Some(1.0),
            "default_joint.friction_angle" => Some(20.0),
            _ => None,
        };
        let d = eval(
            "0.5 * 9.81 * (sin(rad(30)) - cos(rad(30)) * tan(rad(default_joint.friction_angle))) * t^2",
            &var,
        )
        .unwrap();
        assert!((d - 0.9064).abs() < 1e-4, "{d}");
        assert_eq!(eval("-2^2 + 1e1", &var).unwrap(), 6.0);
        assert!(eval("foo + 1", &var).unwrap_err().contains("foo"));
        assert!(eval("(1 + 2", &var).is_err());
    }
}
