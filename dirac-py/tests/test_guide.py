"""docs/python.md's Python as written: every ```python block runs on its own, pasted into a
fresh interpreter started at the repository root, and every result it states in a comment
(`expression   # literal`) is the value the expression has. A snippet that is not meant to run
is written as ```text or ```sh, which this does not read."""

import ast
import io
import pathlib
import re
import tokenize

ROOT = pathlib.Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "python.md"


def python_blocks(text):
    """The ```python blocks of a Markdown text, with the line each starts on."""
    return [(text.count("\n", 0, m.start(1)) + 1, m.group(1))
            for m in re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M)]


def stated_results(source):
    """Line → the literal a comment at the end of the line states, for comments that parse as a
    Python literal (`# (1001, 3)`, `# ['r'], ['phi']`); prose comments are left out."""
    stated = {}
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type != tokenize.COMMENT:
            continue
        try:
            stated[token.start[0]] = ast.literal_eval(token.string[1:].strip())
        except (ValueError, SyntaxError, TypeError, MemoryError, RecursionError):
            pass
    return stated


def run_block(source, name):
    """Runs `source` statement by statement in a fresh namespace; an expression statement whose
    last line ends in a literal comment must evaluate to that literal. Returns how many such
    statements it checked."""
    tree = ast.parse(source, name)
    stated = stated_results(source)
    namespace = {"__name__": "__main__"}
    checked = 0
    for statement in tree.body:
        if isinstance(statement, ast.Expr) and statement.end_lineno in stated:
            code = compile(ast.Expression(statement.value), name, "eval")
            value = eval(code, namespace)
            expected = stated[statement.end_lineno]
            assert value == expected, (
                f"{name}, line {statement.end_lineno}: the comment says {expected!r}, "
                f"the expression is {value!r}")
            checked += 1
        else:
            exec(compile(ast.Module([statement], type_ignores=[]), name, "exec"), namespace)
    return checked


def test_python_guide_runs_as_written(monkeypatch):
    monkeypatch.chdir(ROOT)
    blocks = python_blocks(GUIDE.read_text())
    assert len(blocks) >= 3, "docs/python.md has lost its Python blocks"
    checked = 0
    for line, block in blocks:
        checked += run_block(block, f"docs/python.md, the Python block at line {line}")
    # The shapes, names and symmetry the guide states after its calls.
    assert checked >= 6, checked


def test_a_wrong_stated_result_is_caught():
    source = "x = (2, 3)\nx    # (2, 3)\nlen(x)   # 3\n"
    try:
        run_block(source, "example")
    except AssertionError as error:
        assert "line 3" in str(error) and "says 3" in str(error), error
    else:
        raise AssertionError("a comment stating a wrong result passed")
    assert run_block(source.replace("# 3", "# 2"), "example") == 2
