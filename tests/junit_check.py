"""Checks a `twin test --junit` report: it parses with Python's
xml.etree, validates against Jenkins' JUnit schema (tests/junit-10.xsd,
with the `xmlschema` package), and says what a CI server reads from it.

Usage: python3 tests/junit_check.py REPORT.xml [--runs N] [--no-skipped] [--failed-expectation NAME]

--runs N: the report holds exactly N `run` test cases (one per run).
--no-skipped: no test case was skipped (CI renders: a skipped snapshot
means the renderer found no Vulkan adapter).
--failed-expectation NAME: the report holds a <failure type="expectation">
for NAME whose message names a time (`at … s`) and a value (`=`), and an
[[ATTACHMENT|…png]] line whose file exists.
Exits 1 with the reason when a check fails.
"""

import os
import re
import sys
import xml.etree.ElementTree as ET


def main() -> int:
    args = sys.argv[1:]
    if not args:
        print(__doc__)
        return 2
    report = args[0]
    runs = None
    failed = None
    if "--runs" in args:
        runs = int(args[args.index("--runs") + 1])
    if "--failed-expectation" in args:
        failed = args[args.index("--failed-expectation") + 1]

    root = ET.parse(report).getroot()
    if root.tag != "testsuites":
        return fail(f"root element is <{root.tag}>, not <testsuites>")

    try:
        import xmlschema
    except ImportError:
        return fail("the xmlschema package is missing (pip install xmlschema)")
    schema = xmlschema.XMLSchema(os.path.join(os.path.dirname(__file__), "junit-10.xsd"))
    errors = list(schema.iter_errors(report))
    if errors:
        return fail(f"{report} does not validate against junit-10.xsd: {errors[0]}")

    cases = root.findall("./testsuite/testcase")
    run_cases = [c for c in cases if c.get("name") == "run"]
    if runs is not None and len(run_cases) != runs:
        return fail(f"{len(run_cases)} run test cases, expected {runs}")
    if "--no-skipped" in args:
        skipped = [c for c in cases if c.find("skipped") is not None]
        if skipped:
            why = skipped[0].find("skipped").get("message", "")
            return fail(f"{len(skipped)} test cases skipped, e.g. {skipped[0].get('classname')} {skipped[0].get('name')}: {why}")
    for suite in root.findall("./testsuite"):
        counted = int(suite.get("tests", "-1"))
        if counted != len(suite.findall("testcase")):
            return fail(f"suite {suite.get('name')}: tests = {counted}, but {len(suite.findall('testcase'))} test cases")

    if failed is not None:
        hits = [c for c in cases if c.get("name") == failed and c.find("failure") is not None]
        if not hits:
            return fail(f"no failed test case named {failed!r}")
        f = hits[0].find("failure")
        if f.get("type") != "expectation":
            return fail(f"failure type {f.get('type')!r}, expected 'expectation'")
        message = f.get("message", "")
        if not re.search(r"at [0-9.]+ s", message) or "=" not in message:
            return fail(f"the failure message names no time and value: {message!r}")
        out = hits[0].findtext("system-out") or ""
        pictures = re.findall(r"\[\[ATTACHMENT\|([^\]]+\.png)\]\]", out)
        if not pictures:
            return fail(f"no PNG attachment in <system-out>: {out!r}")
        for p in pictures:
            if not os.path.isfile(p):
                return fail(f"attached picture {p} does not exist")
    print(f"{report}: valid JUnit ({len(root.findall('./testsuite'))} suites, {len(cases)} test cases)")
    return 0


def fail(why: str) -> int:
    print(f"junit_check: {why}", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
