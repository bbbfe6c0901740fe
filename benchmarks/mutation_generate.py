"""Generate mutmut's ``mutants/`` directory (the mutated copy of the packages, one trampoline per
mutated function, and a ``.meta`` file per module listing its mutants) without running any
test: the first step of ``mutation_in_process.py``.  Run from the project root (mutmut reads
``[tool.mutmut]`` in ``pyproject.toml``); needs the ``mutation`` extra.

    python benchmarks/mutation_generate.py
"""

import os

from mutmut.__main__ import (
    copy_also_copy_files,
    copy_src_dir,
    create_mutants,
    setup_source_paths,
    store_lines_covered_by_tests,
)
from mutmut.mutation.trampoline import set_mutant_under_test

set_mutant_under_test("mutant_generation")
os.makedirs("mutants", exist_ok=True)
copy_src_dir()
copy_also_copy_files()
setup_source_paths()
store_lines_covered_by_tests()
print(create_mutants(2))
