"""pycheck.py: the assertion helpers of the Python test programs, as check.h
is the C ones': check() counts a pass or prints "FAIL: what" and counts a
failure; report() prints "N passed, N failed" and exits 1 on a failure;
close() compares numbers within a relative tolerance."""
import sys

_counts = {"passed": 0, "failed": 0}


def check(cond, what):
    if cond:
        _counts["passed"] += 1
    else:
        _counts["failed"] += 1
        print(f"FAIL: {what}", file=sys.stderr)


def close(a, b, tol=1e-9):
    """a within tol of b, relative to |b| (absolute below 1); False when either is None."""
    return a is not None and b is not None and abs(a - b) <= tol * max(1.0, abs(b))


def report():
    print(f"{_counts['passed']} passed, {_counts['failed']} failed")
    sys.exit(1 if _counts["failed"] else 0)
