//! Lowering matrices and vectors: the values of rotation (`3 × 3`) and direction (`3 × 1`)
//! coordinates and what the body computes from them, with nalgebra's spelling so that the
//! user's function still compiles as ordinary Rust: `+ − *` (matrix products, scalar
//! multiples), `/` by a scalar, unary `−`, `.transpose()`, `.trace()`, `.determinant()`,
//! `.dot(&b)`, `.cross(&b)`, `.norm()`, `.norm_squared()`, `.normalize()`, `.cross_matrix()`
//! (`ξ̂`), entries `m[(i, j)]`, `v[i]`, `v.x`, the constructors `Matrix3::identity()`,
//! `Matrix3::zeros()`, `Matrix3::new(..)`, `Matrix3::from_diagonal(&v)`, `Vector3::new(..)`,
//! `Vector3::zeros()`, `Vector3::x()` (`y`, `z`), and `hat(&v)`, `vee(&m)` (`dirac::lie`). Every entry is a node of the
//! graph: a product of matrices is its 27 scalar products, shared by hash-consing.

use quote::ToTokens;
use syn::{BinOp, Expr, Ident, Member};

use super::{Lowering, Operand, Value};
use crate::ir::graph::NodeId;

/// What the body accepts on matrices and vectors, for messages.
pub const MATRIX_ACCEPTED: &str = "on matrices and vectors: `+ - *`, `/` by an f64, unary `-`, \
`.transpose()`, `.trace()`, `.determinant()`, `.dot(&b)`, `.cross(&b)`, `.norm()`, \
`.norm_squared()`, `.normalize()`, `.cross_matrix()`, entries `m[(i, j)]`, `v[i]`, `v.x`, \
`Matrix3::identity()`, `Matrix3::zeros()`, `Matrix3::new(..9 entries)`, \
`Matrix3::from_diagonal(&v)`, `Vector3::new(x, y, z)`, `Vector3::zeros()`, `Vector3::x()` (and \
`y()`, `z()`), `hat(&v)`, `vee(&m)`";

/// A matrix value: `r × c` entries, row by row (a vector is `3 × 1`).
#[derive(Clone, Debug)]
pub struct Mat {
    pub r: usize,
    pub c: usize,
    pub e: Vec<NodeId>,
    /// A rotation coordinate read whole, or its transpose: `(configuration, first entry of the
    /// point, transposed)`. The product `q0.R.transpose() * q1.R` of two such values is the
    /// relative rotation, which the step evaluates from its own increment (see
    /// [`crate::ir::graph::Sym::Rel`]).
    pub origin: Option<(usize, usize, bool)>,
}

impl Mat {
    /// A matrix computed by the body (no coordinate origin).
    pub fn new(r: usize, c: usize, e: Vec<NodeId>) -> Mat {
        Mat {
            r,
            c,
            e,
            origin: None,
        }
    }

    fn at(&self, i: usize, j: usize) -> NodeId {
        self.e[i * self.c + j]
    }

    /// `a 3×3 matrix`, `a 3-vector`.
    pub fn kind(&self) -> String {
        if self.c == 1 {
            format!("a {}-vector", self.r)
        } else {
            format!("a {}×{} matrix", self.r, self.c)
        }
    }
}

impl Lowering<'_> {
    fn mat_error(&self, at: impl ToTokens, message: impl std::fmt::Display) -> Option<Value> {
        self.cx
            .error_spanned_by(at, format!("{message}; accepted {MATRIX_ACCEPTED}"));
        None
    }

    fn build(
        &mut self,
        r: usize,
        c: usize,
        f: impl FnMut(&mut Self, usize, usize) -> NodeId,
    ) -> Mat {
        let mut f = f;
        let mut e = Vec::with_capacity(r * c);
        for i in 0..r {
            for j in 0..c {
                e.push(f(self, i, j));
            }
        }
        Mat::new(r, c, e)
    }

    fn sum(&mut self, terms: impl IntoIterator<Item = NodeId>) -> NodeId {
        let mut terms = terms.into_iter();
        let first = terms.next().unwrap_or_else(|| self.g.constant(0.0));
        terms.fold(first, |acc, t| self.g.add(acc, t))
    }

    /// `+ − * /` with a matrix on at least one side.
    pub(super) fn mat_arith(&mut self, op: BinOp, l: Operand, r: Operand) -> Option<Value> {
        let (le, re) = (l.at, r.at);
        match (op, l.value, r.value) {
            (BinOp::Add(_) | BinOp::Sub(_), Value::Mat(a), Value::Mat(b)) => {
                if (a.r, a.c) != (b.r, b.c) {
                    return self.mat_error(
                        op,
                        format!("cannot add or subtract {} and {}", a.kind(), b.kind()),
                    );
                }
                let add = matches!(op, BinOp::Add(_));
                let e =
                    a.e.iter()
                        .zip(&b.e)
                        .map(|(&x, &y)| {
                            if add {
                                self.g.add(x, y)
                            } else {
                                self.g.sub(x, y)
                            }
                        })
                        .collect();
                Some(Value::Mat(Mat::new(a.r, a.c, e)))
            }
            (BinOp::Mul(_), Value::Mat(a), Value::Mat(b)) => {
                if let Some(rel) = self.relative_rotation(&a, &b) {
                    return Some(Value::Mat(rel));
                }
                if a.c != b.r {
                    let hint = if a.c == 1 && b.c == 1 {
                        ": for the scalar product of two vectors write `a.dot(&b)`"
                    } else {
                        ""
                    };
                    return self.mat_error(
                        op,
                        format!("cannot multiply {} by {}{hint}", a.kind(), b.kind()),
                    );
                }
                let m = self.build(a.r, b.c, |s, i, j| {
                    let terms: Vec<NodeId> =
                        (0..a.c).map(|k| s.g.mul(a.at(i, k), b.at(k, j))).collect();
                    s.sum(terms)
                });
                Some(Value::Mat(m))
            }
            (BinOp::Mul(_), Value::Scalar(x), Value::Mat(a))
            | (BinOp::Mul(_), Value::Mat(a), Value::Scalar(x)) => {
                let e = a.e.iter().map(|&y| self.g.mul(x, y)).collect();
                Some(Value::Mat(Mat::new(a.r, a.c, e)))
            }
            (BinOp::Div(_), Value::Mat(a), Value::Scalar(x)) => {
                let e = a.e.iter().map(|&y| self.g.div(y, x)).collect();
                Some(Value::Mat(Mat::new(a.r, a.c, e)))
            }
            (op, l, r) => {
                let at: &dyn ToTokens = if matches!(l, Value::Mat(_)) { re } else { le };
                self.mat_error(
                    at,
                    format!(
                        "`{}` is not defined between {} and {}",
                        crate::ctxt::show(&op),
                        l.kind(),
                        r.kind()
                    ),
                )
            }
        }
    }

    /// `q0.R.transpose() * q1.R` (the relative rotation `F = R0ᵀ R1`) or
    /// `q1.R.transpose() * q0.R` (`Fᵀ`), read as the symbols `Rel` of `F`'s entries, so that a
    /// step evaluates `F` from its increment `cay(z)` instead of multiplying two stored
    /// rotations: their product carries the round-off of both, an error of `ε` in entries of
    /// size `h` that a discrete Lagrangian divided by `h` would amplify.
    fn relative_rotation(&mut self, a: &Mat, b: &Mat) -> Option<Mat> {
        let (Some((wa, at_a, true)), Some((wb, at_b, false))) = (a.origin, b.origin) else {
            return None;
        };
        if at_a != at_b || wa == wb || wa > 1 || wb > 1 {
            return None;
        }
        // F for (q0ᵀ q1), Fᵀ for (q1ᵀ q0).
        let transposed = wa == 1;
        Some(self.build(3, 3, |s, i, j| {
            let (i, j) = if transposed { (j, i) } else { (i, j) };
            s.g.var(crate::ir::graph::Sym::Rel(at_a + 3 * i + j))
        }))
    }

    /// `−m`.
    pub(super) fn mat_neg(&mut self, a: Mat) -> Value {
        let e = a.e.iter().map(|&x| self.g.neg(x)).collect();
        Value::Mat(Mat::new(a.r, a.c, e))
    }

    /// A method on a matrix or vector.
    pub(super) fn mat_method(&mut self, method: &Ident, a: Mat, args: &[&Expr]) -> Option<Value> {
        let name = method.to_string();
        let arity = match name.as_str() {
            "dot" | "cross" => 1,
            "transpose" | "trace" | "determinant" | "norm" | "norm_squared" | "normalize"
            | "cross_matrix" => 0,
            _ => {
                return self.mat_error(
                    method,
                    format!("unsupported method `{name}` on {}", a.kind()),
                )
            }
        };
        if args.len() != arity {
            return self.mat_error(
                method,
                format!("`{name}` takes {arity} argument(s), found {}", args.len()),
            );
        }
        let square = a.r == a.c;
        let vector3 = (a.r, a.c) == (3, 1);
        match name.as_str() {
            "transpose" => {
                let mut t = self.build(a.c, a.r, |_, i, j| a.at(j, i));
                t.origin = a
                    .origin
                    .map(|(which, at, transposed)| (which, at, !transposed));
                Some(Value::Mat(t))
            }
            "trace" if square => {
                let d: Vec<NodeId> = (0..a.r).map(|i| a.at(i, i)).collect();
                Some(Value::Scalar(self.sum(d)))
            }
            "determinant" if (a.r, a.c) == (3, 3) => {
                let minor = |s: &mut Self, i: usize, j: usize, k: usize, l: usize| {
                    let x = s.g.mul(a.at(i, j), a.at(k, l));
                    let y = s.g.mul(a.at(i, l), a.at(k, j));
                    s.g.sub(x, y)
                };
                let m0 = minor(self, 1, 1, 2, 2);
                let m1 = minor(self, 1, 0, 2, 2);
                let m2 = minor(self, 1, 0, 2, 1);
                let t0 = self.g.mul(a.at(0, 0), m0);
                let t1 = self.g.mul(a.at(0, 1), m1);
                let t2 = self.g.mul(a.at(0, 2), m2);
                let d = self.g.sub(t0, t1);
                Some(Value::Scalar(self.g.add(d, t2)))
            }
            "norm_squared" | "norm" | "normalize" => {
                let squares: Vec<NodeId> = a.e.iter().map(|&x| self.g.mul(x, x)).collect();
                let n2 = self.sum(squares);
                if name == "norm_squared" {
                    return Some(Value::Scalar(n2));
                }
                let n = self.g.fun(crate::ir::graph::Fun::Sqrt, n2);
                if name == "norm" {
                    return Some(Value::Scalar(n));
                }
                let e = a.e.iter().map(|&x| self.g.div(x, n)).collect();
                Some(Value::Mat(Mat::new(a.r, a.c, e)))
            }
            "cross_matrix" if vector3 => Some(Value::Mat(self.hat(&a))),
            "dot" | "cross" => {
                let b = self.expr(args[0])?;
                let Value::Mat(b) = b else {
                    return self.mat_error(
                        args[0],
                        format!("`.{name}(..)` takes {}, found {}", a.kind(), b.kind()),
                    );
                };
                if (a.r, a.c) != (b.r, b.c) || (name == "cross" && !vector3) {
                    return self.mat_error(
                        args[0],
                        format!("`.{name}(..)` of {} and {}", a.kind(), b.kind()),
                    );
                }
                if name == "dot" {
                    let terms: Vec<NodeId> =
                        a.e.iter()
                            .zip(&b.e)
                            .map(|(&x, &y)| self.g.mul(x, y))
                            .collect();
                    return Some(Value::Scalar(self.sum(terms)));
                }
                let m = self.hat(&a);
                let c = self.build(3, 1, |s, i, _| {
                    let t: Vec<NodeId> = (0..3).map(|k| s.g.mul(m.at(i, k), b.e[k])).collect();
                    s.sum(t)
                });
                Some(Value::Mat(c))
            }
            _ => self.mat_error(
                method,
                format!("`.{name}()` is not defined on {}", a.kind()),
            ),
        }
    }

    /// `ξ̂` of a 3-vector.
    fn hat(&mut self, v: &Mat) -> Mat {
        let zero = self.g.constant(0.0);
        let (x, y, z) = (v.e[0], v.e[1], v.e[2]);
        let (nx, ny, nz) = (self.g.neg(x), self.g.neg(y), self.g.neg(z));
        Mat::new(3, 3, vec![zero, nz, y, z, zero, nx, ny, x, zero])
    }

    /// A call of a constructor (`Matrix3::identity()`, `Vector3::new(..)`, …) or of `hat` /
    /// `vee`; `None` (nothing recorded) when `path` names none of them.
    pub(super) fn mat_call(&mut self, path: &syn::Path, args: &[&Expr]) -> Option<Option<Value>> {
        let segs: Vec<String> = path.segments.iter().map(|s| s.ident.to_string()).collect();
        let last = segs.last()?.as_str();
        let ty = (segs.len() >= 2).then(|| segs[segs.len() - 2].as_str());
        let known = matches!(
            (ty, last),
            (Some("Matrix3" | "Vector3"), _) | (_, "hat" | "vee")
        );
        if !known {
            return None;
        }
        let wanted = match (ty, last) {
            (Some("Matrix3"), "identity" | "zeros")
            | (Some("Vector3"), "zeros" | "x" | "y" | "z") => 0,
            (Some("Matrix3"), "new") => 9,
            (Some("Vector3"), "new") => 3,
            (Some("Matrix3"), "from_diagonal") | (_, "hat" | "vee") => 1,
            _ => {
                return Some(self.mat_error(
                    path,
                    format!("unsupported function `{}`", crate::ctxt::show(&path)),
                ))
            }
        };
        if args.len() != wanted {
            return Some(self.mat_error(
                path,
                format!(
                    "`{}` takes {wanted} argument(s), found {}",
                    crate::ctxt::show(&path),
                    args.len()
                ),
            ));
        }
        let values: Option<Vec<Value>> = args.iter().map(|a| self.expr(a)).collect();
        let Some(values) = values else {
            return Some(None);
        };
        Some(self.construct(path, ty, last, values, args))
    }

    fn construct(
        &mut self,
        path: &syn::Path,
        ty: Option<&str>,
        last: &str,
        values: Vec<Value>,
        args: &[&Expr],
    ) -> Option<Value> {
        let (zero, one) = (self.g.constant(0.0), self.g.constant(1.0));
        match (ty, last) {
            (Some("Matrix3"), "identity") => Some(Value::Mat(self.build(3, 3, |_, i, j| {
                if i == j {
                    one
                } else {
                    zero
                }
            }))),
            (Some("Matrix3"), "zeros") => Some(Value::Mat(self.build(3, 3, |_, _, _| zero))),
            (Some("Vector3"), "zeros") => Some(Value::Mat(self.build(3, 1, |_, _, _| zero))),
            (Some("Vector3"), axis @ ("x" | "y" | "z")) => {
                let k = usize::from(axis.as_bytes()[0] - b'x');
                Some(Value::Mat(self.build(3, 1, |_, i, _| {
                    if i == k {
                        one
                    } else {
                        zero
                    }
                })))
            }
            (Some("Matrix3" | "Vector3"), "new") => {
                let mut e = Vec::new();
                for (v, a) in values.into_iter().zip(args) {
                    e.push(self.scalar(v, a)?);
                }
                let r = 3;
                let c = e.len() / 3;
                Some(Value::Mat(Mat::new(r, c, e)))
            }
            (Some("Matrix3"), "from_diagonal") | (_, "hat") => {
                let v = values.into_iter().next().expect("one argument");
                match v {
                    Value::Mat(v) if (v.r, v.c) == (3, 1) => {
                        if last == "hat" {
                            Some(Value::Mat(self.hat(&v)))
                        } else {
                            Some(Value::Mat(self.build(3, 3, |_, i, j| {
                                if i == j {
                                    v.e[i]
                                } else {
                                    zero
                                }
                            })))
                        }
                    }
                    other => self.mat_error(
                        args[0],
                        format!(
                            "`{}` takes a 3-vector, found {}",
                            crate::ctxt::show(&path),
                            other.kind()
                        ),
                    ),
                }
            }
            (_, "vee") => match values.into_iter().next().expect("one argument") {
                Value::Mat(m) if (m.r, m.c) == (3, 3) => {
                    // `m + mᵀ` must vanish: checked at sample configurations later.
                    let mut symmetric = Vec::new();
                    for i in 0..3 {
                        for j in i..3 {
                            symmetric.push(self.g.add(m.at(i, j), m.at(j, i)));
                        }
                    }
                    self.skew
                        .push((symmetric, syn::spanned::Spanned::span(args[0])));
                    // The vector of the skew-symmetric part, as `dirac::lie::vee` computes it.
                    let half = self.g.constant(0.5);
                    let pairs = [((2, 1), (1, 2)), ((0, 2), (2, 0)), ((1, 0), (0, 1))];
                    let e = pairs
                        .iter()
                        .map(|&((a, b), (c, d))| {
                            let diff = self.g.sub(m.at(a, b), m.at(c, d));
                            self.g.mul(half, diff)
                        })
                        .collect();
                    Some(Value::Mat(Mat::new(3, 1, e)))
                }
                other => self.mat_error(
                    args[0],
                    format!("`vee` takes a 3×3 matrix, found {}", other.kind()),
                ),
            },
            _ => unreachable!("mat_call checked the names"),
        }
    }

    /// `m[(i, j)]` or `v[i]`.
    pub(super) fn mat_index(&mut self, a: Mat, index: Value, at: &Expr) -> Option<Value> {
        let (i, j) = match index {
            Value::Int(i) if a.c == 1 => (i, 0),
            Value::Tuple(items) if items.len() == 2 => match (&items[0], &items[1]) {
                (Value::Int(i), Value::Int(j)) => (*i, *j),
                _ => return self.mat_error(at, "entries are read with constant integer indices"),
            },
            other => {
                return self.mat_error(
                    at,
                    format!(
                        "{} is indexed by {}, found {}",
                        a.kind(),
                        if a.c == 1 { "`[i]`" } else { "`[(i, j)]`" },
                        other.kind()
                    ),
                )
            }
        };
        let inside = |x: i64, n: usize| usize::try_from(x).ok().filter(|&x| x < n);
        match (inside(i, a.r), inside(j, a.c)) {
            (Some(i), Some(j)) => Some(Value::Scalar(a.at(i, j))),
            _ => self.mat_error(
                at,
                format!("index ({i}, {j}) is out of range for {}", a.kind()),
            ),
        }
    }

    /// `v.x`, `v.y`, `v.z`.
    pub(super) fn mat_field(&mut self, a: Mat, member: &Member) -> Option<Value> {
        let i = match member {
            Member::Named(id) if id == "x" => 0,
            Member::Named(id) if id == "y" => 1,
            Member::Named(id) if id == "z" => 2,
            _ => 3,
        };
        if a.c != 1 || i >= a.r {
            return self.mat_error(
                member,
                format!("no field `{}` on {}", crate::ctxt::show(&member), a.kind()),
            );
        }
        Some(Value::Scalar(a.e[i]))
    }
}
