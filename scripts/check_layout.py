#!/usr/bin/env python3
"""The tree's layout rules, checked: every module includes only the modules below it, and no source folder
holds more than 25 files. Prints each breach as `file:line: what` and exits 1 if any.
    scripts/check_layout.py [ROOT]
"""
import os
import re
import sys

# Each module and the incise modules its files may include (besides its own). One way: nothing points up.
ALLOWED = {
    'measure': set(),
    'cutting/core': set(),
    'cutting/bspline': {'core'},
    'cutting/mesh': {'core'},
    'cutting/incision': {'core', 'bspline', 'mesh'},
    'cutting/global_dffd': {'core', 'bspline', 'mesh'},
    'cutting/tets': {'core', 'bspline', 'mesh', 'incision'},
    'physics': {'core', 'bspline', 'mesh', 'tets'},
    'devices': set(),
    'sim': {'measure', 'core', 'bspline', 'mesh', 'incision', 'global_dffd', 'tets', 'physics', 'devices'},
    'jobs': {'measure', 'core', 'bspline', 'mesh', 'incision', 'global_dffd', 'tets', 'physics', 'devices', 'sim'},
    'capi': {'core', 'bspline', 'mesh', 'incision', 'global_dffd', 'tets', 'physics', 'devices', 'sim', 'jobs'},
    'python': {'core', 'bspline', 'mesh', 'incision', 'global_dffd', 'tets', 'physics', 'devices', 'sim', 'jobs'},
    'viewer': {'measure', 'core', 'bspline', 'mesh', 'incision', 'global_dffd', 'tets', 'physics', 'devices', 'sim'},
}
MAX_FILES = 25
SOURCE = ('.cpp', '.h', '.c')
INCLUDE = re.compile(r'#include [<"]incise/([a-z_]+)/')


def main(root):
    errors = []
    for module, allowed in ALLOWED.items():
        name = module.rsplit('/', 1)[-1]
        for dirpath, _, files in os.walk(os.path.join(root, module)):
            for f in files:
                if not f.endswith(SOURCE):
                    continue
                path = os.path.join(dirpath, f)
                with open(path, encoding='utf-8') as text:
                    for number, line in enumerate(text, 1):
                        m = INCLUDE.match(line)
                        if m and m.group(1) != name and m.group(1) not in allowed:
                            errors.append(f'{os.path.relpath(path, root)}:{number}: {name} includes incise/{m.group(1)}/, '
                                          f'which it may not (it may include: {", ".join(sorted(allowed)) or "nothing of incise"})')
    for dirpath, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if not d.startswith(('.', 'build', 'out'))]
        sources = [f for f in files if f.endswith(SOURCE)]
        if len(sources) > MAX_FILES:
            errors.append(f'{os.path.relpath(dirpath, root)}: {len(sources)} source files (at most {MAX_FILES}: '
                          'split it by concept)')
    for e in errors:
        print(e)
    return 1 if errors else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '..')))
