"""The repository's own system texts, for the tests: each test runs a system the Rust sources
define, so Python and Rust step the same text."""

import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[2]


def function(path, name):
    """The text of `pub fn name` in a source file of the repository, from its attribute on."""
    source = (ROOT / path).read_text()
    start = source.index(f"pub fn {name}(")
    attr = source.rindex("#[reduced_lagrangian", 0, start)
    end = source.index("\n}\n", start) + 2
    return source[attr:end]
