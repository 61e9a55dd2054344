//! What every run method checks before it runs and how a run ends early: keyword arguments it
//! does not take (a `TypeError` naming the keyword and the closest one it takes), a trajectory
//! that cannot be allocated (`dirac.OutOfMemoryError`, before anything is allocated), and
//! Ctrl-C (`KeyboardInterrupt`, with what was computed before it).

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::OutOfMemoryError;

/// How often the thread that called a run looks at Python's signals while the run works: a
/// Ctrl-C ends the run within this (and the step in progress).
const POLL: Duration = Duration::from_millis(20);

/// The stack of the thread a run works on: the main thread's usual 8 MiB (a spawned thread
/// gets 2 MiB by default, and the fixed-size integrators keep their matrices on the stack).
const RUN_STACK: usize = 8 << 20;

/// The edit distance between `a` and `b` (insertions, deletions, substitutions), by the usual
/// two-row dynamic programme.
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut current = vec![i + 1; b.len() + 1];
        for (j, &cb) in b.iter().enumerate() {
            let substitute = previous[j] + usize::from(ca != cb);
            current[j + 1] = substitute.min(previous[j + 1] + 1).min(current[j] + 1);
        }
        previous = current;
    }
    previous[b.len()]
}

/// The accepted keyword closest to `given`: within an edit distance of a third of its length
/// (at least 1), or sharing its first three letters (`tolerance` → `tol`); `None` when none is
/// close.
fn closest<'a>(given: &str, accepted: &[&'a str]) -> Option<&'a str> {
    let prefix = |a: &str| {
        a.chars()
            .zip(given.chars())
            .take_while(|(x, y)| x == y)
            .count()
    };
    accepted
        .iter()
        .filter(|a| {
            distance(given, a) <= (given.chars().count() / 3).max(1)
                || prefix(a) >= a.chars().count().min(3)
        })
        .min_by_key(|a| distance(given, a))
        .copied()
}

/// The `TypeError` for a keyword argument `given` that `function` does not take: it names the
/// keyword, the closest one it takes, and all it takes (`hint` adds what the keyword means
/// elsewhere, e.g. a start of another method).
pub(crate) fn unexpected_keyword(
    function: &str,
    given: &str,
    accepted: &[&str],
    hint: Option<String>,
) -> PyErr {
    let mut message = format!("{function}() got an unexpected keyword argument '{given}'");
    match (hint, closest(given, accepted)) {
        (Some(hint), _) => message.push_str(&format!(": {hint}.")),
        (None, Some(near)) => message.push_str(&format!("; did you mean '{near}'?")),
        (None, None) => message.push('.'),
    }
    message.push_str(&format!(" It takes: {}.", accepted.join(", ")));
    PyTypeError::new_err(message)
}

/// A `TypeError` for the first keyword of `extra` (the keywords that the signature of
/// `function` did not bind) that is not in `allowed`; `accepted` is everything the function
/// takes, for the message.
pub(crate) fn no_other_keywords(
    function: &str,
    extra: Option<&Bound<'_, PyDict>>,
    allowed: &[&str],
    accepted: &[&str],
    hint: impl Fn(&str) -> Option<String>,
) -> PyResult<()> {
    let Some(extra) = extra else { return Ok(()) };
    for key in extra.keys() {
        let key: String = key.extract()?;
        if !allowed.contains(&key.as_str()) {
            return Err(unexpected_keyword(function, &key, accepted, hint(&key)));
        }
    }
    Ok(())
}

/// Refuses, before anything is allocated, a run whose trajectory needs more memory than can
/// be allocated: `rows` rows of `bytes_per_row` bytes each (the trajectory the integrator
/// collects, its flattened copy, the arrays returned), counted in `u128` so that no size
/// overflows. The whole amount is reserved once, untouched, and released: where the allocator
/// (or the kernel, or an address-space limit) refuses it, the run is refused with
/// `dirac.OutOfMemoryError` (a `MemoryError`) carrying `what` and `bytes`, instead of growing
/// until the process is killed.
pub(crate) fn check_memory(
    what: impl Fn() -> String,
    rows: u128,
    bytes_per_row: u128,
) -> PyResult<()> {
    let bytes = rows.saturating_mul(bytes_per_row);
    if dirac_runtime::linalg::allocatable(bytes) {
        Ok(())
    } else {
        Err(out_of_memory(&what(), bytes))
    }
}

/// `dirac.OutOfMemoryError` for `what`, which needs `bytes` bytes.
pub(crate) fn out_of_memory(what: &str, bytes: u128) -> PyErr {
    let err = OutOfMemoryError::new_err(format!(
        "not enough memory: {what} needs {bytes} bytes ({:.2} GiB), which cannot be allocated; \
         run fewer steps (or write them to Parquet with `write`, in constant memory)",
        bytes as f64 / f64::from(1u32 << 30)
    ));
    Python::with_gil(|py| {
        let value = err.value(py);
        // Attributes on a fresh exception instance: setting them cannot fail.
        let _ = value.setattr("what", what);
        let _ = value.setattr("bytes", bytes);
    });
    err
}

/// The stop condition of an interruptible run: it holds once `cancel` is set, and the run ends
/// after the step in progress, keeping what it computed.
pub(crate) fn until<St>(
    cancel: &AtomicBool,
) -> impl FnMut(usize, f64, &St) -> bool + Clone + Sync + '_ {
    move |_, _, _| cancel.load(Ordering::Relaxed)
}

/// Runs `work` on a thread of its own, with the GIL released, while the calling thread looks
/// at Python's signals every [`POLL`]: when a handler raises (Ctrl-C: `KeyboardInterrupt`),
/// `cancel` is set, so a run stopped by [`until`] ends after its current step; `work`'s result
/// is returned with the exception, for the caller to attach what was computed. Without a
/// signal, the calling thread sleeps until `work` wakes it when done.
pub(crate) fn interruptible<R: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> R + Send,
) -> PyResult<(R, Option<PyErr>)> {
    let cancel = AtomicBool::new(false);
    // Set by the worker when `work` has returned, before it wakes the caller (a thread counts as
    // finished only once its closure's result is stored, a moment later).
    let done = AtomicBool::new(false);
    let outcome = py.allow_threads(|| {
        std::thread::scope(|scope| {
            let caller = std::thread::current();
            let (cancel, done) = (&cancel, &done);
            let worker = std::thread::Builder::new()
                .name("dirac run".into())
                .stack_size(RUN_STACK)
                .spawn_scoped(scope, move || {
                    let result = work(cancel);
                    done.store(true, Ordering::Release);
                    caller.unpark();
                    result
                })?;
            let mut interrupt = None;
            while !done.load(Ordering::Acquire) {
                std::thread::park_timeout(POLL);
                if interrupt.is_none() && !done.load(Ordering::Acquire) {
                    if let Err(e) = Python::with_gil(|py| py.check_signals()) {
                        interrupt = Some(e);
                        cancel.store(true, Ordering::Relaxed);
                    }
                }
            }
            match worker.join() {
                Ok(result) => Ok((result, interrupt)),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        })
    });
    outcome.map_err(|e: std::io::Error| {
        pyo3::exceptions::PyOSError::new_err(format!("a thread for the run: {e}"))
    })
}

/// The exception of an interrupted run with what it computed attached as `name` (the
/// trajectory so far, in the form a completed run returns).
pub(crate) fn interrupted<'py>(
    py: Python<'py>,
    interrupt: PyErr,
    name: &str,
    value: impl IntoPyObject<'py>,
) -> PyErr {
    if let Err(e) = interrupt.value(py).setattr(name, value) {
        return e;
    }
    interrupt
}
