"""Reads back, with pyarrow, the run that the Rust test `files_for_the_python_round_trip`
(dirac-io/tests/parquet.rs) wrote — a directory of parts, dsp.parquet/part-0000k.parquet — and
checks it bit for bit against the values the run computed (written beside it as hexadecimal bit
patterns), together with the documented schema and metadata; then checks that the same
directory with an unfinished part (the hidden partial file a killed run leaves) reads the same.

    python roundtrip.py DIR        # DIR holds dsp.parquet/ and dsp.expected.json

Prints "N passed, M failed" and exits non-zero on any failure.
"""
import json
import shutil
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
    run = directory / "dsp.parquet"
    table = pq.read_table(run)
    expected = json.loads((directory / "dsp.expected.json").read_text())
    parts = sorted(run.glob("part-*.parquet"))
    # The run's description is on every part, its outcome on the last.
    metadata = {k.decode(): v.decode() for k, v in pq.read_metadata(parts[-1]).metadata.items()}
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

    # A killed run's directory: the published parts and the hidden, unfinished part being
    # written (no footer). pyarrow skips names starting with "." and reads the rest.
    killed = directory / "killed.parquet"
    shutil.rmtree(killed, ignore_errors=True)
    killed.mkdir()
    for part in parts[:-1]:
        shutil.copy(part, killed / part.name)
    unfinished = parts[-1].read_bytes()
    (killed / f".{parts[-1].name}.partial").write_bytes(unfinished[: len(unfinished) // 2])
    try:
        published = pq.read_table(killed)
        rows = sum(pq.read_metadata(p).num_rows for p in parts[:-1])
        check("killed run readable", published.num_rows == rows, f"{published.num_rows} rows, {rows} published")
        check(
            "killed run is the published prefix",
            published.column("step").to_pylist() == table.column("step").to_pylist()[:rows],
            "",
        )
    except Exception as e:  # noqa: BLE001 - any failure to read is the failure checked
        check("killed run readable", False, repr(e))

    for f in failed:
        print("FAILED", f)
    print(f"{passed} passed, {len(failed)} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
