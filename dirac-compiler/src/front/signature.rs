//! The function signature: `fn f(q0: Config, q1: Config, h: f64, ...) -> f64` (discrete) or
//! `fn l(q: Config, v: Velocity, ...) -> f64` (continuous, with `rule = ...`).

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::Ident;

use crate::ctxt::Ctxt;
use crate::front::rule::{Rule, RULES};

/// The parsed function signature.
pub struct Signature {
    pub q0: Ident,
    pub q1: Ident,
    pub params: Vec<Ident>,
    /// The time-step parameter.
    pub step: Ident,
    /// Whether the function is a continuous Lagrangian `L(q, v)` (second argument `Velocity`);
    /// then `q0`, `q1` above are the names of `q` and `v`.
    pub continuous: bool,
    /// Whether the time step is a field of the emitted type but not an argument of the function
    /// (a continuous `L` need not take `h`): then it is the last of `params`.
    pub synthetic_step: bool,
}

impl Signature {
    /// The parameters the user's function takes, in order.
    pub fn fn_params(&self) -> &[Ident] {
        let n = self.params.len() - usize::from(self.synthetic_step);
        &self.params[..n]
    }

    /// The index of the time step among [`Self::params`] (the parser puts it there).
    pub fn step_index(&self) -> usize {
        self.params
            .iter()
            .position(|p| *p == self.step)
            .expect("the step is a parameter")
    }

    /// The parameters' names, in order (the time step among them).
    pub fn parameter_names(&self) -> Vec<String> {
        self.params.iter().map(ToString::to_string).collect()
    }
}

/// Checks the function signature: `(q0: Config, q1: Config, p1: f64, ...) -> f64`.
pub fn parse_signature(
    cx: &Ctxt,
    sig: &syn::Signature,
    spec_step: Option<&Ident>,
    rule: Option<&(Ident, Rule)>,
    rule_written: bool,
) -> Option<Signature> {
    let mut ok = true;
    let mut velocity: Option<&syn::Type> = None;
    if let Some(g) = sig.generics.params.first() {
        cx.error_spanned_by(
            g,
            "generic parameters are not supported: the Lagrangian is written over f64",
        );
        ok = false;
    }
    for (token, what) in [
        (sig.asyncness.as_ref().map(|t| t.span()), "`async`"),
        (sig.unsafety.as_ref().map(|t| t.span()), "`unsafe`"),
        (sig.constness.as_ref().map(|t| t.span()), "`const`"),
    ] {
        if let Some(span) = token {
            cx.error_at(span, format!("{what} functions are not supported"));
            ok = false;
        }
    }
    match &sig.output {
        syn::ReturnType::Type(_, ty) if is_f64(ty) => {}
        syn::ReturnType::Type(_, ty) => {
            cx.error_spanned_by(
                ty,
                format!(
                    "a discrete Lagrangian returns `f64`, found `{}`",
                    crate::ctxt::show(&ty)
                ),
            );
            ok = false;
        }
        syn::ReturnType::Default => {
            cx.error_spanned_by(
                &sig.ident,
                "a discrete Lagrangian returns `f64`: add `-> f64`",
            );
            ok = false;
        }
    }
    let mut names = Vec::new();
    for (i, input) in sig.inputs.iter().enumerate() {
        let syn::FnArg::Typed(pat_ty) = input else {
            cx.error_spanned_by(
                input,
                "`self` is not accepted: the Lagrangian is a free function",
            );
            ok = false;
            continue;
        };
        let syn::Pat::Ident(pi) = &*pat_ty.pat else {
            cx.error_spanned_by(&pat_ty.pat, "expected a plain argument name");
            ok = false;
            continue;
        };
        let ty = &*pat_ty.ty;
        if i < 2 && is_type(ty, "Velocity") {
            velocity = Some(ty);
        }
        if i < 2 {
            if !(is_config(ty) || (i == 1 && is_type(ty, "Velocity"))) {
                cx.error_spanned_by(
                    ty,
                    format!(
                        "the first two arguments are the configurations `q0: Config, q1: Config` (or, for a continuous Lagrangian, `q: Config, v: Velocity`), found `{}: {}`",
                        pi.ident,
                        crate::ctxt::show(&ty)
                    ),
                );
                ok = false;
            }
        } else if !is_f64(ty) {
            cx.error_spanned_by(
                ty,
                format!(
                    "parameter `{}` is `{}`; parameters must be `f64` (only scalar parameters are accepted)",
                    pi.ident,
                    crate::ctxt::show(&ty)
                ),
            );
            ok = false;
        }
        names.push(pi.ident.clone());
    }
    if names.len() < 2 {
        cx.error_spanned_by(
            &sig.inputs,
            "expected the configurations first: `fn f(q0: Config, q1: Config, h: f64, ...) -> f64`",
        );
        return None;
    }
    let mut params: Vec<Ident> = names.split_off(2);
    let continuous = velocity.is_some();
    match (velocity, rule) {
        (Some(ty), None) if !rule_written => {
            cx.error_spanned_by(
                ty,
                format!("a continuous Lagrangian `L(q: Config, v: Velocity, ...)` needs a quadrature rule to form L_d; add one of {RULES}"),
            );
            ok = false;
        }
        (None, Some((key, _))) => {
            cx.error_spanned_by(
                key,
                "`rule = ...` discretizes a continuous Lagrangian `fn l(q: Config, v: Velocity, ...)`; this function takes two configurations `(q0: Config, q1: Config)`, so it already is L_d: remove `rule` or make the second argument `v: Velocity`",
            );
            ok = false;
        }
        _ => {}
    }
    // A continuous L need not take the time step: the emitted type gets a field for it anyway.
    let mut synthetic_step = false;
    if continuous {
        let name = spec_step.map_or_else(|| Ident::new("h", Span::call_site()), Clone::clone);
        if !params.contains(&name) {
            params.push(name);
            synthetic_step = true;
        }
    }
    let step = match spec_step {
        Some(step) => {
            if !params.contains(step) {
                let list: Vec<String> = params.iter().map(|p| format!("`{p}`")).collect();
                cx.error_spanned_by(
                    step,
                    format!(
                        "`step = {step}` must name one of the `f64` parameters: {}",
                        list.join(", ")
                    ),
                );
                ok = false;
            }
            Some(step.clone())
        }
        None => params.iter().find(|p| *p == "h").cloned(),
    };
    if step.is_none() && ok {
        cx.error_spanned_by(
            &sig.ident,
            "no time step: name a parameter `h: f64`, or declare which parameter it is with `step = <name>`",
        );
        ok = false;
    }
    let step = step.filter(|_| ok)?;
    Some(Signature {
        q0: names[0].clone(),
        q1: names[1].clone(),
        params,
        step,
        continuous,
        synthetic_step,
    })
}

/// Checks `controls(...)` against the signature: each control is one of the function's `f64`
/// parameters, and not the time step.
pub fn check_controls(cx: &Ctxt, controls: &[Ident], sig: &Signature) {
    for c in controls {
        if *c == sig.step {
            cx.error_spanned_by(
                c,
                format!("`{c}` is the time step and cannot be a control: a control is a parameter that a control law sets before every step"),
            );
        } else if !sig.fn_params().contains(c) {
            let list: Vec<String> = sig.fn_params().iter().map(|p| format!("`{p}`")).collect();
            cx.error_spanned_by(
                c,
                format!(
                    "control `{c}` is not a parameter of the function; a control is one of its `f64` parameters ({}): add `{c}: f64` to the signature",
                    if list.is_empty() { "it has none".to_string() } else { list.join(", ") }
                ),
            );
        }
    }
}

fn is_f64(ty: &syn::Type) -> bool {
    matches!(ty, syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident("f64"))
}

fn is_config(ty: &syn::Type) -> bool {
    is_type(ty, "Config")
}

fn is_type(ty: &syn::Type, name: &str) -> bool {
    matches!(ty, syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident(name))
}
