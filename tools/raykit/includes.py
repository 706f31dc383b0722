"""A step file's standard-library names and the headers that declare them: one verdict on every
standard library.

A file that uses std::unique_ptr without #include <memory> compiles where another header happens to
bring <memory> (a Mac's libc++ does, through <vector> or <functional>) and fails where none does (the grader's
libstdc++). The C++ standard says which header declares each name, so the kit reads the student's
file and says, in its own words and the same words everywhere, which header to add: under the step
in the student's own `./kit check`, and first in the compile error a grader shows when the file
does not compile there.

What counts as included: the file's own #include <...> lines, and those of the kit's headers it
includes ("raykit/..."), through their own quoted includes: include/raykit/ray.hpp brings the
headers a step may use without including them (so they are the same on every library). A header
the file names but this table does not know is ignored; a name this table does not know is never
reported. Comments and literals are not read.
"""

from __future__ import annotations

import re
from contextlib import suppress
from dataclasses import dataclass
from pathlib import Path

# The header that declares each name (C++17, [headers] and each clause's synopsis). A name some
# other standard header also declares lists those in ALSO.
HEADERS = {
    "<algorithm>": "adjacent_find all_of any_of binary_search clamp copy_backward copy_if copy_n count count_if "
                   "equal equal_range fill fill_n find find_end find_first_of find_if find_if_not for_each "
                   "generate generate_n includes inplace_merge is_heap is_partitioned is_permutation is_sorted "
                   "is_sorted_until lexicographical_compare lower_bound make_heap max max_element merge min "
                   "min_element minmax minmax_element mismatch next_permutation none_of nth_element partial_sort "
                   "partial_sort_copy partition partition_copy partition_point pop_heap prev_permutation push_heap "
                   "remove remove_copy remove_copy_if remove_if replace replace_copy replace_copy_if replace_if "
                   "reverse reverse_copy rotate rotate_copy sample search search_n set_difference "
                   "set_intersection set_symmetric_difference set_union shuffle sort sort_heap stable_partition "
                   "stable_sort swap_ranges transform unique unique_copy upper_bound",
    "<any>": "any any_cast bad_any_cast make_any",
    "<array>": "array",
    "<bitset>": "bitset",
    "<cassert>": "",
    "<chrono>": "chrono",
    "<cmath>": "acos asin atan atan2 cbrt ceil copysign cos cosh erf exp exp2 expm1 fabs fdim floor fma fmax fmin "
               "fmod fpclassify frexp hypot ilogb isfinite isgreater isinf isless isnan isnormal ldexp lgamma "
               "llround log log10 log1p log2 logb lround modf nan nearbyint nextafter nexttoward pow remainder "
               "remquo rint round scalbn signbit sin sinh sqrt tan tanh tgamma trunc",
    "<complex>": "complex",
    "<cstdint>": "int8_t int16_t int32_t int64_t intmax_t intptr_t uint8_t uint16_t uint32_t uint64_t uintmax_t "
                 "uintptr_t int_fast32_t uint_fast32_t int_least32_t uint_least32_t",
    "<cstdio>": "FILE fclose fflush fgets fopen fprintf fputs fread fscanf fwrite getchar perror printf putchar puts "
                "remove rename scanf snprintf sprintf sscanf vsnprintf",
    "<cstdlib>": "abort atexit atof atoi atol div exit free getenv labs llabs malloc qsort quick_exit rand "
                 "realloc srand strtod strtof strtol strtoul system",
    "<cstring>": "memchr memcmp memcpy memmove memset strcat strchr strcmp strcpy strerror strlen strncmp strncpy "
                 "strrchr strstr",
    "<deque>": "deque",
    "<exception>": "exception exception_ptr rethrow_exception current_exception terminate uncaught_exceptions",
    "<fstream>": "fstream ifstream ofstream",
    "<functional>": "bind cref divides equal_to function greater greater_equal invoke less less_equal "
                    "logical_and logical_not logical_or mem_fn minus modulus multiplies negate not_equal_to not_fn "
                    "plus ref reference_wrapper",
    "<iomanip>": "get_money put_money quoted setfill setprecision setw",
    "<ios>": "boolalpha defaultfloat fixed hexfloat noboolalpha scientific",
    "<iostream>": "cerr cin clog cout",
    "<istream>": "istream ws",
    "<iterator>": "advance back_inserter distance front_inserter inserter istream_iterator iterator_traits "
                  "make_reverse_iterator move_iterator next ostream_iterator prev reverse_iterator",
    "<limits>": "numeric_limits",
    "<list>": "list",
    "<map>": "map multimap",
    "<memory>": "allocator make_shared make_unique shared_ptr unique_ptr weak_ptr addressof",
    "<mutex>": "lock_guard mutex unique_lock",
    "<numeric>": "accumulate adjacent_difference exclusive_scan gcd inclusive_scan inner_product iota lcm "
                 "partial_sum reduce transform_exclusive_scan transform_inclusive_scan transform_reduce",
    "<optional>": "bad_optional_access make_optional nullopt nullopt_t optional",
    "<ostream>": "endl ends flush ostream",
    "<queue>": "priority_queue queue",
    "<random>": "bernoulli_distribution default_random_engine minstd_rand mt19937 mt19937_64 normal_distribution "
                "random_device uniform_int_distribution uniform_real_distribution",
    "<set>": "multiset set",
    "<sstream>": "istringstream ostringstream stringstream",
    "<stack>": "stack",
    "<stdexcept>": "domain_error invalid_argument length_error logic_error out_of_range overflow_error "
                   "range_error runtime_error underflow_error",
    "<string>": "getline stod stof stoi stol stold stoll stoul stoull string to_string to_wstring wstring",
    "<string_view>": "string_view",
    "<thread>": "thread this_thread",
    "<tuple>": "apply forward_as_tuple make_from_tuple make_tuple tie tuple tuple_cat",
    "<type_traits>": "conditional_t decay_t enable_if enable_if_t is_floating_point_v is_integral_v is_same "
                     "is_same_v remove_cv_t remove_reference_t",
    "<unordered_map>": "unordered_map unordered_multimap",
    "<unordered_set>": "unordered_multiset unordered_set",
    "<utility>": "as_const declval exchange forward make_pair move pair swap",
    "<valarray>": "valarray",
    "<variant>": "get_if holds_alternative monostate variant visit",
    "<vector>": "vector",
}
# Names that more than one header declares (the standard says so): any of them will do.
ALSO = {
    "abs": ("<cstdlib>", "<cmath>"), "size_t": ("<cstddef>", "<cstdio>", "<cstdlib>", "<cstring>", "<ctime>"),
    "ptrdiff_t": ("<cstddef>",), "nullptr_t": ("<cstddef>",), "byte": ("<cstddef>",),
    "swap": ("<utility>", "<algorithm>"), "move": ("<utility>", "<algorithm>"),
    "getline": ("<string>", "<istream>"), "endl": ("<ostream>", "<iostream>"), "ostream": ("<ostream>", "<iostream>"),
    "istream": ("<istream>", "<iostream>"), "begin": ("<iterator>", "<array>", "<vector>", "<string>", "<map>",
                                                      "<set>", "<deque>", "<list>", "<unordered_map>"),
    "remove": ("<algorithm>", "<cstdio>"),
    "fixed": ("<ios>", "<iostream>", "<sstream>", "<iomanip>"), "scientific": ("<ios>", "<iostream>", "<sstream>"),
    "initializer_list": ("<initializer_list>", "<vector>", "<array>", "<algorithm>", "<utility>", "<string>"),
    "hash": ("<functional>", "<string>", "<memory>", "<optional>", "<variant>"),
}
ALSO["end"] = ALSO["size"] = ALSO["data"] = ALSO["empty"] = ALSO["begin"]
ALSO["get"] = ("<tuple>", "<utility>", "<array>", "<variant>")

MARK = "which this file does not #include"     # in every finding: compile_errors keeps such lines


def _table() -> dict[str, tuple[str, ...]]:
    table: dict[str, tuple[str, ...]] = {}
    for header, names in HEADERS.items():
        for name in names.split():
            table[name] = (header,)
    table.update(ALSO)
    return table


TABLE = _table()


@dataclass(frozen=True)
class Finding:
    file: str       # the file's name, as the student knows it (its step folder and name)
    line: int
    name: str
    header: str     # the header to add: the first the standard names

    def text(self) -> str:
        return (f"{self.file}:{self.line}: std::{self.name} is declared in {self.header}, {MARK}: add "
                f"#include {self.header} at its top. It compiles only where another header happens to bring "
                f"{self.header}, and the grader's standard library may not.")


def code_only(text: str, strings: bool = False) -> str:
    """`text` with its comments and (unless `strings`) its string and character literals blanked
    (newlines kept, so line numbers stay)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j]))
            i = j
        elif strings and text[i] in "\"'R":
            out.append(c)
            i += 1
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^ ()\\\t\n]{0,16})\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            j = text.find(")" + m.group(1) + '"', i)
            j = n if j < 0 else j + len(m.group(1)) + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                out.append(c)           # a digit separator (1'000), not a character literal
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + " " * max(0, j - i - 2) + (c if j - i >= 2 else ""))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)
USE = re.compile(r"(?<![\w:])(?:::\s*)?std\s*::\s*([A-Za-z_]\w*)")


def included(text: str, here: Path | None, include_root: Path, seen: set[Path] | None = None) -> set[str]:
    """The standard headers `text` includes: its own <...> lines, and those of the headers it includes
    with quotes that are found beside it (`here`) or under `include_root` (the kit's), recursively."""
    seen = set() if seen is None else seen
    found: set[str] = set()
    for kind, name in INCLUDE.findall(code_only(text, strings=True)):
        if kind == "<":
            found.add(f"<{name.strip()}>")
            continue
        for base in ([here] if here else []) + [include_root]:
            path = (base / name).resolve()
            if path.is_file() and path not in seen:
                seen.add(path)
                with suppress(OSError):
                    found |= included(path.read_text(errors="replace")[:1_000_000], path.parent, include_root, seen)
                break
    return found


def findings(path: Path, shown_name: str, include_root: Path) -> list[Finding]:
    """The names of the standard library `path` uses whose header it does not include (itself or
    through the kit's headers): the first use of each, in order."""
    try:
        text = path.read_text(errors="replace")[:1_000_000]
    except OSError:
        return []
    have = included(text, path.parent, include_root)
    code = code_only(text)
    out, reported = [], set()
    for m in USE.finditer(code):
        name = m.group(1)
        headers = TABLE.get(name)
        if not headers or name in reported or any(h in have for h in headers):
            continue
        reported.add(name)
        out.append(Finding(shown_name, code.count("\n", 0, m.start()) + 1, name, headers[0]))
    return out


def step_findings(steps_dir: Path, folder: str, files: list[str], include_root: Path) -> list[str]:
    """Every finding of a step's files, as text."""
    return [f.text() for name in files for f in findings(steps_dir / folder / name, f"{folder}/{name}", include_root)]
