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

thread_local! {
    /// Whether this thread compiles a system given as text ([`crate::text`]) rather than
    /// expanding an attribute inside rustc.
    static TEXT: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f` as a compilation of text: [`show`] prints tokens as rustc would.
pub fn as_text<R>(f: impl FnOnce() -> R) -> R {
    struct Reset(bool);
    impl Drop for Reset {
        fn drop(&mut self) {
            TEXT.with(|t| t.set(self.0));
        }
    }
    let _reset = Reset(TEXT.with(|t| t.replace(true)));
    f()
}

/// The user's tokens as an error message quotes them. Inside rustc that is rustc's own printing;
/// for text parsed at run time, `proc_macro2` would put a space between every two tokens
/// (`q1 . x`), so rustc's rules are applied here: tokens that cross into a procedural macro keep
/// only the jointness of punctuation, and rustc's pretty printer spaces the rest (none around
/// `.`, none before `,` and `;`, none between a name and its parenthesized arguments).
pub fn show<T: ToTokens>(tokens: &T) -> String {
    let stream = tokens.to_token_stream();
    if !TEXT.with(std::cell::Cell::get) {
        return stream.to_string();
    }
    let mut out = String::new();
    print_tts(stream, &mut out);
    out
}

fn print_tts(stream: proc_macro2::TokenStream, out: &mut String) {
    use proc_macro2::{Delimiter, Spacing, TokenTree};
    let trees: Vec<TokenTree> = stream.into_iter().collect();
    for (i, tt) in trees.iter().enumerate() {
        match tt {
            TokenTree::Group(g) => {
                let (open, close) = match g.delimiter() {
                    Delimiter::Parenthesis => ("(", ")"),
                    Delimiter::Bracket => ("[", "]"),
                    Delimiter::Brace => ("{ ", " }"),
                    Delimiter::None => ("", ""),
                };
                out.push_str(open);
                print_tts(g.stream(), out);
                out.push_str(close);
            }
            other => out.push_str(&other.to_string()),
        }
        let Some(next) = trees.get(i + 1) else {
            break;
        };
        let joint = matches!(tt, TokenTree::Punct(p) if p.spacing() == Spacing::Joint);
        if !joint && space_between(tt, next) {
            out.push(' ');
        }
    }
}

/// rustc's `space_between` (`rustc_ast_pretty`): whether two tokens that do not touch in the
/// source are printed with a space between them.
fn space_between(a: &proc_macro2::TokenTree, b: &proc_macro2::TokenTree) -> bool {
    use proc_macro2::{Delimiter, TokenTree};
    let punct = |t: &TokenTree, c: char| matches!(t, TokenTree::Punct(p) if p.as_char() == c);
    let is_punct = |t: &TokenTree| matches!(t, TokenTree::Punct(_));
    if punct(a, '.') && !is_punct(b) {
        return false;
    }
    if !is_punct(a) && (punct(b, ',') || punct(b, ';') || punct(b, '.')) {
        return false;
    }
    if let (TokenTree::Ident(_), TokenTree::Group(g)) = (a, b) {
        if g.delimiter() == Delimiter::Parenthesis {
            return false;
        }
    }
    if punct(a, '#') && matches!(b, TokenTree::Group(g) if g.delimiter() == Delimiter::Bracket) {
        return false;
    }
    true
}
