#!/usr/bin/env python3
"""Fails when a Catch2 test name holds a ';' or starts with '-' or '~'. catch_discover_tests
hands ctest each name as a CMake list element, so a ';' splits it, and ctest runs a filter that
matches no test case: "No tests ran", status 0 -- the test silently never runs. A leading '-' is
read as an option, a leading '~' as "every test but this one".
    check_test_names.py build/tests/rayproc_tests
"""
import subprocess
import sys

# Catch2 v2 exits with the number of names listed: the status says nothing here.
names = subprocess.run([sys.argv[1], "--list-test-names-only"], check=False,
                       capture_output=True, text=True).stdout.splitlines()
bad = [n for n in names if ";" in n or n.strip().startswith(("-", "~"))]
for n in bad:
    print("test name ctest would not run as such: " + n.strip())
print("%d test names, %d unsafe" % (len(names), len(bad)))
sys.exit(1 if bad else 0)
