#!/usr/bin/env python3
"""Fails when a Catch2 test name holds a ';'. catch_discover_tests hands ctest each name as a
CMake list element, so such a name is split, and ctest runs a filter that matches no test case:
"No tests ran", status 0 -- the test silently never runs.
    check_test_names.py build/tests/rayproc_tests
"""
import subprocess
import sys

# Catch2 v2 exits with the number of names listed: the status says nothing here.
names = subprocess.run([sys.argv[1], "--list-test-names-only"], check=False,
                       capture_output=True, text=True).stdout.splitlines()
bad = [n for n in names if ";" in n]
for n in bad:
    print("test name with ';' (ctest would not run it): " + n.strip())
print("%d test names, %d with ';'" % (len(names), len(bad)))
sys.exit(1 if bad else 0)
