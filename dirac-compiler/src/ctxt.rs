//! Error collection: every mistake is recorded with its span, and one compilation reports all of
//! them (the `Ctxt` of serde_derive).
//!
//! A context belongs to one phase of the compiler (the attribute and signature, the lowering,
//! the invariance check): the phase records into it, then [`Ctxt::finish`] consumes it and says
//! whether the phase's result may be used. A context dropped without being finished panics, so
//! no error can be recorded and then forgotten, and no later phase has to poll for errors.

use std::cell::RefCell;
use std::fmt::Display;

use proc_macro2::Span;
use quote::ToTokens;

/// The errors of one phase.
pub struct Ctxt {
    /// `None` once finished.
    errors: RefCell<Option<Vec<syn::Error>>>,
}

impl Ctxt {
    /// A context with no errors.
    pub fn new() -> Self {
        Ctxt {
            errors: RefCell::new(Some(Vec::new())),
        }
    }

    fn push(&self, error: syn::Error) {
        self.errors
            .borrow_mut()
            .as_mut()
            .expect("a finished Ctxt records no errors")
            .push(error);
    }

    /// Records an error pointing at `tokens`.
    pub fn error_spanned_by<T: ToTokens, M: Display>(&self, tokens: T, message: M) {
        self.push(syn::Error::new_spanned(tokens.into_token_stream(), message));
    }

    /// Records an error at `span`.
    pub fn error_at<M: Display>(&self, span: Span, message: M) {
        self.push(syn::Error::new(span, message));
    }

    /// Records a parse error.
    pub fn syn_error(&self, error: syn::Error) {
        self.push(error);
    }

    /// Ends the phase: its `value` if it recorded no error, else every error combined into one.
    /// A phase that fails records why; should one return `None` without a message, that is a
    /// bug of the compiler, reported as such rather than as a panic.
    pub fn finish<T>(self, value: Option<T>) -> Result<T, syn::Error> {
        let errors = self
            .errors
            .borrow_mut()
            .take()
            .expect("a Ctxt is finished once");
        let mut errors = errors.into_iter();
        match (errors.next(), value) {
            (None, Some(value)) => Ok(value),
            (None, None) => Err(syn::Error::new(
                Span::call_site(),
                "internal error in dirac-compiler: a stage failed without reporting why; please report this",
            )),
            (Some(mut combined), _) => {
                for e in errors {
                    combined.combine(e);
                }
                Err(combined)
            }
        }
    }
}

impl Drop for Ctxt {
    fn drop(&mut self) {
        if self.errors.borrow().is_some() && !std::thread::panicking() {
            panic!(
                "dirac-compiler: a Ctxt was dropped without `finish`, so its errors would be lost"
            );
        }
    }
}

impl Default for Ctxt {
    fn default() -> Self {
        Ctxt::new()
    }
}
