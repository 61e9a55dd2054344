//! A test body run again in a child process, so that an abort (e.g. a failed allocation) ends
//! the child, not the test harness.

/// In the harness: runs the test `name` of this binary again in a child process — under an
/// address-space limit of `limit_kb` KiB (`ulimit -v`) when given — asserts that it succeeded
/// and printed `expected`, and returns `false` (the caller returns). In that child: returns
/// `true`, and the caller runs the test's body.
pub fn in_child(name: &str, limit_kb: Option<u64>, expected: &str) -> bool {
    if std::env::var_os("DIRAC_TEST_CHILD").is_some() {
        return true;
    }
    let exe = std::env::current_exe().expect("the test binary");
    let mut command = match limit_kb {
        Some(kb) => {
            let mut sh = std::process::Command::new("sh");
            sh.arg("-c")
                .arg(format!("ulimit -v {kb} && exec \"$0\" \"$@\""))
                .arg(exe);
            sh
        }
        None => std::process::Command::new(exe),
    };
    let out = command
        .args(["--exact", name, "--nocapture", "--test-threads=1"])
        .env("DIRAC_TEST_CHILD", "1")
        .output()
        .expect("the child runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains(expected),
        "the child ended with {:?}\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    false
}
