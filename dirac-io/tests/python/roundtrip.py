"""Reads back, with pyarrow, the Parquet file that the Rust test
`files_for_the_python_round_trip` (dirac-io/tests/parquet.rs) wrote, and checks it bit for bit
against the values the run computed (written beside it as hexadecimal bit patterns), together
with the documented schema and metadata.

    python roundtrip.py DIR        # DIR holds dsp.parquet and dsp.expected.json

Prints "N passed, M failed" and exits non-zero on any failure.
"""
import json
import struct
import sys
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq


def bits(value):
    """The 64-bit pattern of a float, as the Rust side writes it."""
    return None if value is None else format(struct.unpack("<Q", struct.pack("<d", value))[0], "016x")


def main(directory):
    directory = Path(directory)
    table = pq.read_table(directory / "dsp.parquet")
    expected = json.loads((directory / "dsp.expected.json").read_text())
    metadata = {k.decode(): v.decode() for k, v in pq.read_metadata(directory / "dsp.parquet").metadata.items()}
    passed, failed = 0, []

    def check(name, ok, detail=""):
        nonlocal passed
        if ok:
            passed += 1
        else:
            failed.append(f"{name}: {detail}")

    columns = [c for c in expected if c != "metadata"]
    check("schema", table.column_names == columns, f"{table.column_names} != {columns}")
    check("step type", table.schema.field("step").type == pa.uint64(), str(table.schema.field("step").type))
    check("iterations type", table.schema.field("iterations").type == pa.uint32(), "")
    check("residual nullable", table.schema.field("residual").nullable, "")
    for name in columns:
        if name not in table.column_names:
            check(name, False, "missing")
            continue
        values = table.column(name).to_pylist()
        if name in ("step", "iterations"):
            got = values
            want = expected[name]
        else:
            got = [bits(v) for v in values]
            want = expected[name]
        mismatch = next((i for i, (g, w) in enumerate(zip(got, want)) if g != w), None)
        check(
            name,
            len(got) == len(want) and mismatch is None,
            f"{len(got)} rows against {len(want)}"
            + ("" if mismatch is None else f"; row {mismatch}: {got[mismatch]} != {want[mismatch]}"),
        )
    for key, value in expected["metadata"].items():
        got = metadata.get(key)
        if key == "dirac.parameter.m2":
            got = bits(float(got)) if got is not None else None
        check(key, got == value, f"{got!r} != {value!r}")

    for f in failed:
        print("FAILED", f)
    print(f"{passed} passed, {len(failed)} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
