#!/usr/bin/env python3
"""Fails when a Catch2 test name holds a semicolon: CMake's catch_discover_tests splits such a name into
list items, each a filter that matches no test, so ctest would report the test passed without running it."""
import subprocess
import sys

names = subprocess.run([sys.argv[1], "--list-test-names-only"], capture_output=True, text=True, check=False).stdout.splitlines()
bad = [name for name in names if chr(59) in name]
for name in bad:
    print("test name holds a semicolon (ctest would never run it): " + name)
sys.exit(1 if bad or not names else 0)
