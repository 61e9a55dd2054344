//! The examples' command line, written once: every example declares its options here (flag, value
//! name, help, default, what a good value is) and gets typed values back. An unknown flag, a
//! missing value or a value that does not parse or fails its check stops the example with a
//! message and exit status 2 instead of being ignored; `--help` (or `-h`) prints the options and
//! their defaults and exits with status 0.
//!
//! ```ignore
//! let mut cli = Cli::new("cluster", "Lennard-Jones clusters, one build for every size");
//! let sizes = cli.list("--n", "N1,N2,..", "cluster sizes", &[64, 128, 256], at_least(2));
//! let steps = cli.value("--steps", "S", "steps per run", 300, at_least(10));
//! cli.finish(); // exits here on --help or on any bad argument
//! ```
//!
//! A token that starts with `--` (or is `-h`) is a flag; a token that follows a flag and is not
//! itself one is that flag's value (`--flag=value` works too; a switch given a value is an
//! error), so values cannot start with `--`, and negative numbers (`-1`) are values. Each flag
//! may be given once. Included with `#[path]` by every example, by the dirac-io ones too (a
//! separate workspace, the same file), and copied into the scratch crates of `scaling`.

#![allow(dead_code)]

use std::fmt::Display;
use std::path::PathBuf;
use std::str::FromStr;

/// A type a flag's value parses to.
pub trait Value: FromStr + Clone {
    /// What a value of this type is, for messages when any parsed value is accepted.
    const ANY: &'static str;
    /// The noun that a bound qualifies: "an integer" in "an integer ≥ 10".
    const NOUN: &'static str;
    /// The value as written on the command line (for defaults in `--help`).
    fn show(&self) -> String;
    /// Whether the value is finite (always, except for floating-point infinities and NaN).
    fn finite(&self) -> bool {
        true
    }
}

macro_rules! integer_value {
    ($($t:ty),*) => {$(
        impl Value for $t {
            const ANY: &'static str = "a non-negative integer";
            const NOUN: &'static str = "an integer";
            fn show(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
integer_value!(usize, u32, u64);

impl Value for f64 {
    const ANY: &'static str = "a number";
    const NOUN: &'static str = "a number";
    fn show(&self) -> String {
        self.to_string()
    }
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl Value for String {
    const ANY: &'static str = "a value";
    const NOUN: &'static str = "a value";
    fn show(&self) -> String {
        self.clone()
    }
}

impl Value for PathBuf {
    const ANY: &'static str = "a path";
    const NOUN: &'static str = "a path";
    fn show(&self) -> String {
        self.display().to_string()
    }
}

/// What a good value is: a test and its description ("an integer ≥ 10"); for a list, also
/// whether it may be empty.
pub struct Check<T> {
    what: String,
    ok: Box<dyn Fn(&T) -> bool>,
    none_ok: bool,
}

impl<T> Check<T> {
    /// A value that passes `ok`, described by `what` in messages and in `--help`.
    pub fn new(what: impl Into<String>, ok: impl Fn(&T) -> bool + 'static) -> Self {
        Check {
            what: what.into(),
            ok: Box::new(ok),
            none_ok: false,
        }
    }

    /// The same check on each item of a list that may also be empty (`--flag ''`: none).
    pub fn or_none(self) -> Self {
        Check {
            none_ok: true,
            ..self
        }
    }
}

/// Any value that parses (floating-point values finite).
pub fn any<T: Value>() -> Check<T> {
    Check::new(T::ANY, |v: &T| v.finite())
}

/// A finite value `≥ min`.
pub fn at_least<T: Value + PartialOrd + Display + 'static>(min: T) -> Check<T> {
    Check::new(format!("{} ≥ {min}", T::NOUN), move |v: &T| {
        v.finite() && *v >= min
    })
}

/// A finite value `> min`.
pub fn greater_than<T: Value + PartialOrd + Display + 'static>(min: T) -> Check<T> {
    Check::new(format!("{} > {min}", T::NOUN), move |v: &T| {
        v.finite() && *v > min
    })
}

/// One line of `--help`.
struct Help {
    flag: &'static str,
    meta: String,
    text: String,
}

/// The parsed command line and the options declared so far.
pub struct Cli {
    name: &'static str,
    about: &'static str,
    /// The flags given, with their values (`None` when the next token is another flag or there is
    /// none), and whether an option has claimed them.
    given: Vec<(String, Option<String>, bool)>,
    help: Vec<Help>,
    errors: Vec<String>,
}

impl Cli {
    /// The command line of this process; `name` is the example's name in the usage line,
    /// `about` what it does (the first line of `--help`).
    pub fn new(name: &'static str, about: &'static str) -> Self {
        // `args_os`, not `args`: an argument that is not UTF-8 is an error, not a panic.
        let mut not_utf8 = Vec::new();
        let args: Vec<String> = std::env::args_os()
            .skip(1)
            .map(|a| {
                a.into_string().unwrap_or_else(|a| {
                    let lossy = a.to_string_lossy().into_owned();
                    not_utf8.push(format!("argument `{lossy}` is not valid UTF-8"));
                    lossy
                })
            })
            .collect();
        let mut cli = Self::from_args(name, about, args);
        cli.errors.splice(0..0, not_utf8);
        cli
    }

    /// The same from given arguments (without the program name).
    pub fn from_args(
        name: &'static str,
        about: &'static str,
        args: impl IntoIterator<Item = String>,
    ) -> Self {
        let mut cli = Cli {
            name,
            about,
            given: Vec::new(),
            help: Vec::new(),
            errors: Vec::new(),
        };
        let is_flag = |s: &str| s.starts_with("--") || s == "-h";
        let mut args = args.into_iter().peekable();
        while let Some(arg) = args.next() {
            if !is_flag(&arg) {
                cli.errors.push(format!("unexpected argument `{arg}`"));
                continue;
            }
            if let Some((flag, value)) = arg.split_once('=') {
                cli.given
                    .push((flag.to_owned(), Some(value.to_owned()), false));
                continue;
            }
            let value = args.next_if(|next| !is_flag(next));
            cli.given.push((arg, value, false));
        }
        cli
    }

    /// Claims `flag`: its value if given (`Some(None)` when given without one), with an error
    /// recorded if it was given more than once.
    fn claim(&mut self, flag: &'static str) -> Option<Option<String>> {
        let mut found = None;
        let mut count = 0;
        for (f, value, used) in &mut self.given {
            if f == flag {
                *used = true;
                count += 1;
                found.get_or_insert_with(|| value.clone());
            }
        }
        if count > 1 {
            self.errors.push(format!("{flag} is given {count} times"));
        }
        found
    }

    fn document(&mut self, flag: &'static str, meta: &str, text: String) {
        let meta = meta.to_owned();
        self.help.push(Help { flag, meta, text });
    }

    /// Parses and checks one value of `flag`; records an error and returns `None` if it fails.
    fn parse<T: Value>(&mut self, flag: &str, raw: &str, check: &Check<T>) -> Option<T> {
        match raw.trim().parse::<T>() {
            Ok(v) if (check.ok)(&v) => Some(v),
            _ => {
                self.errors
                    .push(format!("{flag}: `{raw}` is not {}", check.what));
                None
            }
        }
    }

    /// The raw value of a flag that takes one, with an error recorded if it came without.
    fn raw(&mut self, flag: &'static str, meta: &str) -> Option<String> {
        match self.claim(flag)? {
            Some(raw) => Some(raw),
            None => {
                self.errors.push(format!("{flag} needs a value {meta}"));
                None
            }
        }
    }

    /// `--flag VALUE`, `default` when absent.
    pub fn value<T: Value>(
        &mut self,
        flag: &'static str,
        meta: &'static str,
        help: &str,
        default: T,
        check: Check<T>,
    ) -> T {
        let text = format!("{help}: {} (default {})", check.what, default.show());
        self.document(flag, meta, text);
        match self.raw(flag, meta) {
            Some(raw) => self.parse(flag, &raw, &check).unwrap_or(default),
            None => default,
        }
    }

    /// `--flag VALUE`, `None` when absent.
    pub fn optional<T: Value>(
        &mut self,
        flag: &'static str,
        meta: &'static str,
        help: &str,
        check: Check<T>,
    ) -> Option<T> {
        self.document(flag, meta, format!("{help}: {} (optional)", check.what));
        let raw = self.raw(flag, meta)?;
        self.parse(flag, &raw, &check)
    }

    /// `--flag A|B|..`, one of the named `choices`; `default` (one of their names) when absent.
    pub fn choice<T: Clone>(
        &mut self,
        flag: &'static str,
        help: &str,
        default: &str,
        choices: &[(&'static str, T)],
    ) -> T {
        let names: Vec<&str> = choices.iter().map(|(name, _)| *name).collect();
        let meta = names.join("|");
        self.document(flag, &meta, format!("{help} (default {default})"));
        let pick = |name: &str| {
            choices
                .iter()
                .find(|(n, _)| *n == name)
                .map(|(_, v)| v.clone())
        };
        let fallback = pick(default).expect("the default is one of the choices");
        match self.raw(flag, &meta) {
            Some(raw) => pick(raw.trim()).unwrap_or_else(|| {
                self.errors.push(format!(
                    "{flag}: `{raw}` is not one of {}",
                    names.join(", ")
                ));
                fallback
            }),
            None => fallback,
        }
    }

    /// `--flag A,B,..`: a comma-separated list, each item passing `check`, not empty unless the
    /// check is [`Check::or_none`]'s (then `--flag ''` gives no items); `default` when absent.
    pub fn list<T: Value>(
        &mut self,
        flag: &'static str,
        meta: &'static str,
        help: &str,
        default: &[T],
        check: Check<T>,
    ) -> Vec<T> {
        let empty_ok = check.none_ok;
        let shown: Vec<String> = default.iter().map(Value::show).collect();
        let empty = if empty_ok { "; '' for none" } else { "" };
        let text = format!(
            "{help}: each {}{empty} (default {})",
            check.what,
            shown.join(",")
        );
        self.document(flag, meta, text);
        let Some(raw) = self.raw(flag, meta) else {
            return default.to_vec();
        };
        if raw.trim().is_empty() {
            if !empty_ok {
                self.errors.push(format!("{flag} needs at least one value"));
            }
            return Vec::new();
        }
        let items: Vec<Option<T>> = raw
            .split(',')
            .map(|item| self.parse(flag, item, &check))
            .collect();
        items.into_iter().collect::<Option<_>>().unwrap_or_default()
    }

    /// `--flag` alone: whether it is given.
    pub fn switch(&mut self, flag: &'static str, help: &str) -> bool {
        self.document(flag, "", help.to_owned());
        match self.claim(flag) {
            Some(Some(value)) => {
                self.errors
                    .push(format!("{flag} takes no value (given `{value}`)"));
                true
            }
            Some(None) => true,
            None => false,
        }
    }

    /// `--out DIR`, the output directory, `default` when absent.
    pub fn out_dir(&mut self, default: impl Into<PathBuf>) -> PathBuf {
        let help = "where the figures and tables are written";
        self.value("--out", "DIR", help, default.into(), any())
    }

    /// Records an error found by the example itself (a combination of values it cannot use).
    pub fn reject(&mut self, message: impl Into<String>) {
        self.errors.push(message.into());
    }

    /// The usage line.
    fn usage(&self) -> String {
        let mut line = format!("usage: {}", self.name);
        for h in &self.help {
            if h.meta.is_empty() {
                line += &format!(" [{}]", h.flag);
            } else {
                line += &format!(" [{} {}]", h.flag, h.meta);
            }
        }
        line
    }

    /// The `--help` text.
    fn help_text(&self) -> String {
        let mut text = format!("{}: {}\n\n{}\n", self.name, self.about, self.usage());
        let rows: Vec<(String, &str)> = self
            .help
            .iter()
            .map(|h| {
                (
                    format!("{} {}", h.flag, h.meta).trim_end().to_owned(),
                    h.text.as_str(),
                )
            })
            .chain([("-h, --help".to_owned(), "print this help")])
            .collect();
        let width = rows
            .iter()
            .map(|(l, _)| l.chars().count())
            .max()
            .unwrap_or(0);
        text += "\noptions:\n";
        for (left, right) in rows {
            let pad = width - left.chars().count();
            text += &format!("  {left}{:pad$}  {right}\n", "");
        }
        text
    }

    /// What the command line asks for once every option is declared: `Ok(true)` to run,
    /// `Ok(false)` for `--help`, or the message for the first bad argument.
    pub fn check(mut self) -> Result<bool, String> {
        let help = self.claim("--help").is_some() | self.claim("-h").is_some();
        if help {
            return Ok(false);
        }
        let unknown: Vec<String> = self
            .given
            .iter()
            .filter(|(_, _, used)| !used)
            .map(|(flag, _, _)| format!("unknown flag `{flag}`"))
            .collect();
        self.errors.extend(unknown);
        match self.errors.first() {
            None => Ok(true),
            Some(first) => Err(format!(
                "{}: {first}\n{}\n(--help describes the options)",
                self.name,
                self.usage()
            )),
        }
    }

    /// Ends the declarations: on `--help` prints the options and exits with status 0; on a bad
    /// argument prints the first error and the usage line to stderr and exits with status 2.
    pub fn finish(self) {
        let help = self.help_text();
        match self.check() {
            Ok(true) => {}
            Ok(false) => {
                print!("{help}");
                std::process::exit(0)
            }
            Err(message) => {
                eprintln!("{message}");
                std::process::exit(2)
            }
        }
    }
}
