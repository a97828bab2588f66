//! A typed reader over a parsed TOML table that knows the path of every field, so each error
//! names it (`lights[2].intensity`), and that rejects unknown keys (a typo is an error, not a
//! silently ignored field).

use std::cell::RefCell;

use glam::Vec3;
use toml::{Table, Value};

use crate::error::SceneError;

/// One TOML table being read: its file, its path, and the keys read so far.
pub(crate) struct Fields<'a> {
    file: &'a str,
    path: String,
    table: &'a Table,
    used: RefCell<Vec<&'a str>>,
}

/// The TOML type name of a value, for messages.
fn type_name(v: &Value) -> &'static str {
    match v {
        Value::String(_) => "a string",
        Value::Integer(_) => "an integer",
        Value::Float(_) => "a number",
        Value::Boolean(_) => "a boolean",
        Value::Datetime(_) => "a date",
        Value::Array(_) => "an array",
        Value::Table(_) => "a table",
    }
}

/// A number as the user would write it (`1e40`, not forty digits).
fn show(n: f64) -> String {
    if n.is_finite() && n != 0.0 && !(1e-4..1e6).contains(&n.abs()) {
        format!("{n:e}")
    } else {
        format!("{n}")
    }
}

/// A number (integer or float) as f64.
fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Integer(i) => Some(*i as f64),
        Value::Float(f) => Some(*f),
        _ => None,
    }
}

impl<'a> Fields<'a> {
    /// The root table of `file`.
    pub(crate) fn root(file: &'a str, table: &'a Table) -> Self {
        Fields {
            file,
            path: String::new(),
            table,
            used: RefCell::new(Vec::new()),
        }
    }

    /// The file name used in messages.
    pub(crate) fn file(&self) -> &'a str {
        self.file
    }

    /// The full path of `key` in this table.
    pub(crate) fn path_of(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_owned()
        } else {
            format!("{}.{key}", self.path)
        }
    }

    /// An error about `key`.
    pub(crate) fn error(&self, key: &str, what: impl Into<String>) -> SceneError {
        SceneError::field(self.file, self.path_of(key), what)
    }

    /// An error about this table as a whole (path `self`).
    pub(crate) fn error_here(&self, what: impl Into<String>) -> SceneError {
        SceneError::field(self.file, self.path.clone(), what)
    }

    /// The raw value of `key`, marking it read.
    pub(crate) fn get(&self, key: &'a str) -> Option<&'a Value> {
        let v = self.table.get(key);
        if v.is_some() {
            self.used.borrow_mut().push(key);
        }
        v
    }

    /// A finite number.
    pub(crate) fn f32(&self, key: &'a str) -> Result<Option<f32>, SceneError> {
        let Some(v) = self.get(key) else {
            return Ok(None);
        };
        let n = number(v)
            .ok_or_else(|| self.error(key, format!("expected a number, found {}", type_name(v))))?;
        let f = n as f32;
        if !f.is_finite() {
            return Err(self.error(key, format!("must be a finite number, got {}", show(n))));
        }
        Ok(Some(f))
    }

    /// A number that may also be `inf` (TOML's positive infinity, as written, not a finite
    /// number too large for f32).
    pub(crate) fn f32_or_inf(&self, key: &'a str) -> Result<Option<f32>, SceneError> {
        match self.table.get(key) {
            Some(Value::Float(f)) if *f == f64::INFINITY => {
                self.get(key);
                Ok(Some(f32::INFINITY))
            }
            Some(Value::Float(f)) if f.is_nan() || *f == f64::NEG_INFINITY => {
                self.get(key);
                Err(self.error(
                    key,
                    format!("must be a number >= 0 or inf, got {}", show(*f)),
                ))
            }
            _ => self.f32(key),
        }
    }

    /// A required finite number.
    pub(crate) fn req_f32(&self, key: &'a str) -> Result<f32, SceneError> {
        self.f32(key)?.ok_or_else(|| self.error(key, "missing"))
    }

    /// A non-negative integer that fits `u32`.
    pub(crate) fn u32(&self, key: &'a str) -> Result<Option<u32>, SceneError> {
        let Some(v) = self.get(key) else {
            return Ok(None);
        };
        match v {
            Value::Integer(i) => u32::try_from(*i)
                .map(Some)
                .map_err(|_| self.error(key, format!("expected a whole number >= 0, got {i}"))),
            _ => Err(self.error(
                key,
                format!("expected a whole number, found {}", type_name(v)),
            )),
        }
    }

    /// A boolean.
    pub(crate) fn bool(&self, key: &'a str) -> Result<Option<bool>, SceneError> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Boolean(b)) => Ok(Some(*b)),
            Some(v) => Err(self.error(
                key,
                format!("expected true or false, found {}", type_name(v)),
            )),
        }
    }

    /// A string.
    pub(crate) fn str(&self, key: &'a str) -> Result<Option<&'a str>, SceneError> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::String(s)) => Ok(Some(s.as_str())),
            Some(v) => Err(self.error(key, format!("expected a string, found {}", type_name(v)))),
        }
    }

    /// Three finite numbers.
    pub(crate) fn vec3(&self, key: &'a str) -> Result<Option<Vec3>, SceneError> {
        let Some(v) = self.get(key) else {
            return Ok(None);
        };
        let Value::Array(items) = v else {
            return Err(self.error(key, format!("expected 3 numbers, found {}", type_name(v))));
        };
        if items.len() != 3 {
            return Err(self.error(key, format!("expected 3 numbers, found {}", items.len())));
        }
        let mut out = [0.0f32; 3];
        for (o, item) in out.iter_mut().zip(items) {
            let n = number(item).ok_or_else(|| {
                self.error(
                    key,
                    format!("expected 3 numbers, found {} in the list", type_name(item)),
                )
            })?;
            *o = n as f32;
            if !o.is_finite() {
                return Err(self.error(key, format!("must be finite, got {}", show(n))));
            }
        }
        Ok(Some(Vec3::from_array(out)))
    }

    /// A list of finite numbers (`[0, 0.5, 1]`).
    pub(crate) fn f32s(&self, key: &'a str) -> Result<Option<Vec<f32>>, SceneError> {
        let Some(v) = self.get(key) else {
            return Ok(None);
        };
        let Value::Array(items) = v else {
            return Err(self.error(
                key,
                format!("expected a list of numbers, found {}", type_name(v)),
            ));
        };
        let mut out = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let n = number(item).ok_or_else(|| {
                self.error(
                    &format!("{key}[{i}]"),
                    format!("expected a number, found {}", type_name(item)),
                )
            })?;
            let f = n as f32;
            if !f.is_finite() {
                return Err(self.error(
                    &format!("{key}[{i}]"),
                    format!("must be finite, got {}", show(n)),
                ));
            }
            out.push(f);
        }
        Ok(Some(out))
    }

    /// A list of lists of `n` finite numbers (`[[0, 0, 0], [1, 0, 0]]`).
    pub(crate) fn rows(&self, key: &'a str, n: usize) -> Result<Option<Vec<Vec<f32>>>, SceneError> {
        let Some(v) = self.get(key) else {
            return Ok(None);
        };
        let Value::Array(items) = v else {
            return Err(self.error(
                key,
                format!(
                    "expected a list of lists of {n} numbers, found {}",
                    type_name(v)
                ),
            ));
        };
        let mut out = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let at = format!("{key}[{i}]");
            let Value::Array(row) = item else {
                return Err(self.error(
                    &at,
                    format!("expected {n} numbers, found {}", type_name(item)),
                ));
            };
            if row.len() != n {
                return Err(self.error(&at, format!("expected {n} numbers, found {}", row.len())));
            }
            let mut r = Vec::with_capacity(n);
            for x in row {
                let v = number(x).ok_or_else(|| {
                    self.error(
                        &at,
                        format!("expected {n} numbers, found {} in the list", type_name(x)),
                    )
                })?;
                let f = v as f32;
                if !f.is_finite() {
                    return Err(self.error(&at, format!("must be finite, got {}", show(v))));
                }
                r.push(f);
            }
            out.push(r);
        }
        Ok(Some(out))
    }

    /// A required vector.
    pub(crate) fn req_vec3(&self, key: &'a str) -> Result<Vec3, SceneError> {
        self.vec3(key)?.ok_or_else(|| self.error(key, "missing"))
    }

    /// An RGB value: three non-negative numbers, or one number for grey.
    pub(crate) fn color(&self, key: &'a str) -> Result<Option<Vec3>, SceneError> {
        let c = match self.table.get(key) {
            Some(v) if number(v).is_some() => self.f32(key)?.map(Vec3::splat),
            _ => self.vec3(key)?,
        };
        if let Some(c) = c
            && c.min_element() < 0.0
        {
            return Err(self.error(
                key,
                format!("must be non-negative, got [{}, {}, {}]", c.x, c.y, c.z),
            ));
        }
        Ok(c)
    }

    /// A colour with an opacity: `"transparent"` (black, 0), four numbers `[r, g, b, a]`
    /// (colour non-negative, `a` in `[0, 1]`), or a colour as [`Fields::color`] reads it
    /// (opacity 1).
    pub(crate) fn color_alpha(&self, key: &'a str) -> Result<Option<(Vec3, f32)>, SceneError> {
        match self.table.get(key) {
            Some(Value::String(s)) if s == "transparent" => {
                self.get(key);
                Ok(Some((Vec3::ZERO, 0.0)))
            }
            Some(Value::String(s)) => {
                self.get(key);
                Err(self.error(
                    key,
                    format!("expected 3 or 4 numbers or \"transparent\", got \"{s}\""),
                ))
            }
            Some(Value::Array(items)) if items.len() == 4 => {
                let v = self.f32s(key)?.unwrap_or_default();
                let (rgb, a) = (Vec3::new(v[0], v[1], v[2]), v[3]);
                if rgb.min_element() < 0.0 {
                    return Err(self.error(
                        key,
                        format!(
                            "colour must be non-negative, got [{}, {}, {}]",
                            v[0], v[1], v[2]
                        ),
                    ));
                }
                if !(0.0..=1.0).contains(&a) {
                    return Err(self.error(key, format!("alpha must be in [0, 1], got {a}")));
                }
                Ok(Some((rgb, a)))
            }
            _ => Ok(self.color(key)?.map(|c| (c, 1.0))),
        }
    }

    /// A sub-table.
    pub(crate) fn table(&self, key: &'a str) -> Result<Option<Fields<'a>>, SceneError> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Table(t)) => Ok(Some(Fields {
                file: self.file,
                path: self.path_of(key),
                table: t,
                used: RefCell::new(Vec::new()),
            })),
            Some(v) => Err(self.error(key, format!("expected a table, found {}", type_name(v)))),
        }
    }

    /// An array of tables (`[[lights]]`), each with the path `key[i]`.
    pub(crate) fn tables(&self, key: &'a str) -> Result<Vec<Fields<'a>>, SceneError> {
        match self.get(key) {
            None => Ok(Vec::new()),
            Some(Value::Array(items)) => items
                .iter()
                .enumerate()
                .map(|(i, item)| match item {
                    Value::Table(t) => Ok(Fields {
                        file: self.file,
                        path: format!("{}[{i}]", self.path_of(key)),
                        table: t,
                        used: RefCell::new(Vec::new()),
                    }),
                    v => Err(self.error(
                        &format!("{key}[{i}]"),
                        format!("expected a table, found {}", type_name(v)),
                    )),
                })
                .collect(),
            Some(v) => Err(self.error(
                key,
                format!("expected an array of tables, found {}", type_name(v)),
            )),
        }
    }

    /// The entries of a table of tables (`[materials.NAME]`), in key order.
    pub(crate) fn named_tables(
        &self,
        key: &'a str,
    ) -> Result<Vec<(&'a str, Fields<'a>)>, SceneError> {
        let Some(outer) = self.table(key)? else {
            return Ok(Vec::new());
        };
        let mut out = Vec::new();
        for name in outer.table.keys() {
            let t = outer
                .table(name.as_str())?
                .ok_or_else(|| outer.error(name, "missing"))?;
            out.push((name.as_str(), t));
        }
        Ok(out)
    }

    /// Fails on any key that was not read: a typo must not be ignored.
    pub(crate) fn finish(&self, known: &[&str]) -> Result<(), SceneError> {
        let used = self.used.borrow();
        for key in self.table.keys() {
            if !used.contains(&key.as_str()) {
                return Err(self.error(
                    key,
                    format!("unknown field (expected one of: {})", known.join(", ")),
                ));
            }
        }
        Ok(())
    }
}

/// A name from a fixed list, or an error listing the choices.
pub(crate) fn choose<T: Copy>(
    f: &Fields<'_>,
    key: &str,
    value: &str,
    choices: &[(&str, T)],
) -> Result<T, SceneError> {
    choices
        .iter()
        .find(|(n, _)| *n == value)
        .map(|(_, t)| *t)
        .ok_or_else(|| {
            let names: Vec<String> = choices.iter().map(|(n, _)| format!("\"{n}\"")).collect();
            f.error(
                key,
                format!("unknown value \"{value}\" (expected {})", names.join(", ")),
            )
        })
}
