#!/usr/bin/env python3
"""Translate one pFUnit 4 suite (.pf) into a plain Fortran test program (pfunit_lite).

Usage: pf2f90.py test_x.pf -o test_x.f90 [--no-line-directives]

The output holds
  (a) the suite's module, copied line by line, with every `@assertX(args)` line replaced by
      `call assertX(args, location=SourceLocation('test_x.pf', LINE))` and
      `if (anyExceptions()) return` (as pFUnit 4 expands it), and the other directives turned
      into comments;
  (b) a program that runs every @test (with the @before/@after routines around it) through
      funit_run_test of tests/pfunit_lite/funit.f90, counts @disable'd tests as skipped, prints
      `N passed, N failed, N skipped` and ends with `error stop 1` when a test failed.

The output contains `#line` directives that point compiler messages at the .pf file, and
`#ifdef`/`#ifndef` for `@test(ifdef=X)`/`@test(ifndef=X)`, so it must be compiled with the
preprocessor on (gfortran -cpp; CMake property Fortran_PREPROCESS). Generated statements are
split with `&` to stay under 100 columns. The supported subset is the one in PFUNIT.md; any
other directive is an error. Errors go to stderr as `file:line: error: ...`, exit status 2.
Python 3 standard library only.
"""

import argparse
import os
import re
import sys

WIDTH = 99

# Directive (lower case) -> (Fortran procedure name, minimum number of arguments).
ASSERTIONS = {
    'assertequal': ('assertEqual', 2),
    'assertnotequal': ('assertNotEqual', 2),
    'asserttrue': ('assertTrue', 1),
    'assertfalse': ('assertFalse', 1),
    'assertlessthan': ('assertLessThan', 2),
    'assertlessthanorequal': ('assertLessThanOrEqual', 2),
    'assertgreaterthan': ('assertGreaterThan', 2),
    'assertgreaterthanorequal': ('assertGreaterThanOrEqual', 2),
    'assertrelativelyequal': ('assertRelativelyEqual', 3),
    'assertall': ('assertAll', 1),
    'assertany': ('assertAny', 1),
    'assertnone': ('assertNone', 1),
    'assertnotall': ('assertNotAll', 1),
    'assertisfinite': ('assertIsFinite', 1),
    'assertisnan': ('assertIsNaN', 1),
    'assertfail': ('assertFail', 1),
}

# Directives that PFUNIT.md rules out, with the reason given to the user.
FORBIDDEN = {
    'assertisinfinite': 'does not compile in pFUnit 4.12; use @assertFalse(ieee_is_finite(x)) '
                        'together with @assertFalse(ieee_is_nan(x))',
    'assertthat': 'does not compile in pFUnit 4.12',
    'suite': 'breaks pFUnit\'s automatic suite registry; the suite is named after the module',
    'mpitest': 'MPI tests are not supported',
    'testcase': 'fixtures are not supported by pfunit_lite; use @before/@after with module '
                'variables, or a loop over cases inside one test',
    'testparameter': 'parameterized tests are not supported by pfunit_lite; loop over the '
                     'cases inside one test with message= naming the case',
}

DIRECTIVE_RE = re.compile(r'^(\s*)@(\w+)(.*)$')
MODULE_RE = re.compile(r'^\s*module\s+(\w+)\s*(!.*)?$', re.IGNORECASE)
SUBROUTINE_RE = re.compile(r'^\s*subroutine\s+(\w+)\s*(\((.*)\))?\s*(!.*)?$', re.IGNORECASE)
ANY_SUBROUTINE_RE = re.compile(r'^\s*(\w+\s+)*subroutine\s+\w+', re.IGNORECASE)


class PfError(Exception):
    """A problem in the .pf file, reported as `file:line: error: message`."""

    def __init__(self, lineno, message):
        super().__init__(message)
        self.lineno = lineno
        self.message = message


# --------------------------------------------------------------------------------------------
# Small Fortran lexing helpers (strings are '...' or "..." with doubled quotes inside)
# --------------------------------------------------------------------------------------------

def scan(text):
    """Yield (index, char, in_string) for text, tracking Fortran character literals."""
    quote = None
    for i, ch in enumerate(text):
        if quote:
            if ch == quote:
                quote = None  # a doubled quote reopens on the next character
                yield i, ch, True
                continue
            yield i, ch, True
        else:
            if ch in '\'"':
                quote = ch
                yield i, ch, True
                continue
            yield i, ch, False


def matching_paren(text, start):
    """Index of the ')' closing the '(' at text[start], or None; raises on '!' outside strings."""
    depth = 0
    for i, ch, in_string in scan(text[start:]):
        if in_string:
            continue
        if ch == '(':
            depth += 1
        elif ch == ')':
            depth -= 1
            if depth == 0:
                return start + i
        elif ch == '!':
            raise ValueError('comment')
    return None


def split_top_level(text, sep=','):
    """Split text at `sep` characters outside strings and parentheses/brackets."""
    parts, depth, cur = [], 0, []
    for _, ch, in_string in scan(text):
        if not in_string:
            if ch in '([':
                depth += 1
            elif ch in ')]':
                depth -= 1
            elif ch == sep and depth == 0:
                parts.append(''.join(cur))
                cur = []
                continue
        cur.append(ch)
    parts.append(''.join(cur))
    return [p.strip() for p in parts]


def is_comment_or_blank(line):
    stripped = line.strip()
    return not stripped or stripped.startswith('!')


def split_statement(indent, text, width=WIDTH):
    """Lay out one generated statement in lines of at most `width` columns.

    Breaks after commas outside strings first; a piece that is still too long (a long string
    literal, say) is cut anywhere with `&` at the end of the line and `&` at the start of the
    next, which free form allows inside tokens and character literals alike.
    """
    if len(indent) + len(text) <= width:
        return [indent + text]
    cont = indent + '   '
    segments, cur = [], []
    for _, ch, in_string in scan(text):
        cur.append(ch)
        if ch == ',' and not in_string:
            segments.append(''.join(cur))
            cur = []
    if cur:
        segments.append(''.join(cur))

    lines, line = [], indent
    for seg in segments:
        if line.strip() and len(line) + len(seg.rstrip()) + 2 > width:
            lines.append(line.rstrip() + ' &')
            line = cont
            seg = seg.lstrip()
        while len(line) + len(seg) + 2 > width:
            n = width - 1 - len(line)
            while n > 1 and seg[n - 1] == ' ':  # never end a chunk on a blank
                n -= 1
            lines.append(line + seg[:n] + '&')
            seg = seg[n:]
            line = cont + '&'
        line += seg
    lines.append(line.rstrip())
    return lines


def fortran_string(text):
    return "'" + text.replace("'", "''") + "'"


def cpp_string(text):
    return '"' + text.replace('\\', '\\\\').replace('"', '\\"') + '"'


# --------------------------------------------------------------------------------------------
# Translation
# --------------------------------------------------------------------------------------------

class Test:
    def __init__(self, lineno, ifdef=None, ifndef=None):
        self.lineno = lineno
        self.ifdef = ifdef
        self.ifndef = ifndef
        self.disabled = False
        self.name = None


def parse_test_options(rest, lineno):
    """Options of `@test(...)`: only ifdef=MACRO and ifndef=MACRO are supported."""
    ifdef = ifndef = None
    rest = rest.strip()
    if not rest:
        return ifdef, ifndef
    if not rest.startswith('('):
        raise PfError(lineno, 'unexpected text after @test (pFUnit allows no comment or other '
                              'text on a directive line)')
    try:
        close = matching_paren(rest, 0)
    except ValueError:
        close = None
    if close is None or rest[close + 1:].strip():
        raise PfError(lineno, 'malformed @test(...) options (one directive per line, no '
                              'trailing comment, no & continuation)')
    for option in split_top_level(rest[1:close]):
        if not option:
            continue
        m = re.match(r'^(\w+)\s*=\s*(.*)$', option)
        key = m.group(1).lower() if m else option.lower()
        if key == 'npes':
            raise PfError(lineno, '@test(npes=...): MPI tests are not supported')
        if not m or key not in ('ifdef', 'ifndef') or not re.match(r'^\w+$', m.group(2)):
            raise PfError(lineno, f'unsupported @test option "{option}" (pfunit_lite supports '
                                  'ifdef=MACRO and ifndef=MACRO)')
        if key == 'ifdef':
            ifdef = m.group(2)
        else:
            ifndef = m.group(2)
    return ifdef, ifndef


def parse_assertion(name, rest, lineno):
    """Return the argument text of `@name(args)`, checked against the directive rules."""
    canonical, min_args = ASSERTIONS[name]
    stripped = rest.strip()
    if stripped.endswith('&'):
        raise PfError(lineno, f'@{canonical} continued with &: a directive must fit on one line')
    if not stripped.startswith('('):
        raise PfError(lineno, f'@{canonical} needs its arguments in parentheses on the same line')
    offset = rest.index('(')
    try:
        close = matching_paren(rest, offset)
    except ValueError:
        raise PfError(lineno, f'comment inside @{canonical}(...): pFUnit allows no comment on a '
                              'directive line') from None
    if close is None:
        raise PfError(lineno, f'unbalanced parentheses in @{canonical}(...): a directive must '
                              'fit on one line')
    trailing = rest[close + 1:].strip()
    if trailing:
        raise PfError(lineno, f'unexpected text "{trailing}" after @{canonical}(...) (pFUnit '
                              'allows no trailing comment on a directive line)')
    args = rest[offset + 1:close].strip()
    parts = split_top_level(args) if args else []
    if len(parts) < min_args or any(not p for p in parts):
        raise PfError(lineno, f'@{canonical} needs at least {min_args} argument(s), got '
                              f'"{args}"')
    for p in parts:
        if re.match(r'^location\s*=', p, re.IGNORECASE):
            raise PfError(lineno, f'@{canonical}: location= is added by the translator')
    return canonical, args


def translate(pf_path, out_path, line_directives=True):
    with open(pf_path, encoding='latin-1') as fh:
        lines = fh.read().splitlines()

    base = os.path.splitext(os.path.basename(pf_path))[0]
    pf_name = os.path.basename(pf_path)
    pf_cpp = cpp_string(os.path.abspath(pf_path))

    out = [f'! Generated by pf2f90.py (pfunit_lite) from {pf_name}; do not edit.']
    if line_directives:
        out.append(f'#line 1 {pf_cpp}')

    module_name = None
    tests = []
    before = after = None
    pending_test = None      # Test waiting for its subroutine statement
    pending_fixture = None   # ('before'|'after', lineno) waiting for its subroutine

    for lineno, line in enumerate(lines, start=1):
        m = DIRECTIVE_RE.match(line)
        if m:
            indent, word, rest = m.group(1), m.group(2), m.group(3)
            key = word.lower()
            if pending_fixture:
                raise PfError(lineno, f'@{pending_fixture[0]} must be followed by its '
                                      '`subroutine name()` line')
            if key in FORBIDDEN or key.startswith('mpiassert'):
                reason = FORBIDDEN.get(key, 'MPI assertions are not supported')
                raise PfError(lineno, f'@{word}: {reason}')
            if key == 'test':
                if pending_test:
                    raise PfError(lineno, '@test follows another @test without a subroutine')
                ifdef, ifndef = parse_test_options(rest, lineno)
                pending_test = Test(lineno, ifdef, ifndef)
                out.append(indent + '!' + line.lstrip())
            elif key == 'disable':
                if rest.strip():
                    raise PfError(lineno, 'unexpected text after @disable')
                if not pending_test:
                    raise PfError(lineno, '@disable must sit between @test and its subroutine')
                pending_test.disabled = True
                out.append(indent + '!' + line.lstrip())
            elif key in ('before', 'after'):
                if rest.strip():
                    raise PfError(lineno, f'unexpected text after @{key}')
                if pending_test:
                    raise PfError(lineno, f'@{key} between @test and its subroutine')
                if (before if key == 'before' else after) is not None:
                    raise PfError(lineno, f'a second @{key} in one file')
                pending_fixture = (key, lineno)
                out.append(indent + '!' + line.lstrip())
            elif key in ASSERTIONS:
                canonical, args = parse_assertion(key, rest, lineno)
                if pending_test:
                    raise PfError(lineno, f'@{canonical} between @test and its subroutine')
                if line_directives and out[-1] != f'#line {lineno} {pf_cpp}':
                    out.append(f'#line {lineno} {pf_cpp}')
                call = (f'call {canonical}({args}, '
                        f'location=SourceLocation({fortran_string(pf_name)}, {lineno}))')
                out.extend(split_statement(indent, call))
                out.append(indent + 'if (anyExceptions()) return')
                if line_directives:
                    out.append(f'#line {lineno + 1} {pf_cpp}')
            elif key.startswith('assert'):
                raise PfError(lineno, f'@{word} is not supported by pfunit_lite (see '
                                      'tests/pfunit_lite/README.md for the supported list)')
            else:
                raise PfError(lineno, f'unknown directive @{word}')
            continue

        if pending_fixture and not is_comment_or_blank(line):
            kind, _ = pending_fixture
            sm = SUBROUTINE_RE.match(line)
            if not sm or (sm.group(3) or '').strip():
                raise PfError(lineno, f'@{kind} must be followed by `subroutine name()` (no '
                                      'arguments)')
            if kind == 'before':
                before = sm.group(1)
            else:
                after = sm.group(1)
            pending_fixture = None
        elif pending_test and not is_comment_or_blank(line) and not line.lstrip().startswith('#'):
            sm = SUBROUTINE_RE.match(line)
            if not sm:
                if ANY_SUBROUTINE_RE.match(line):
                    raise PfError(lineno, 'pFUnit recognises only a plain `subroutine name()` '
                                          'line after @test (no prefixes such as recursive)')
                raise PfError(lineno, 'expected `subroutine name()` after @test (line '
                                      f'{pending_test.lineno})')
            if (sm.group(3) or '').strip():
                raise PfError(lineno, 'a test subroutine takes no arguments (fixtures and '
                                      'parameters are not supported)')
            pending_test.name = sm.group(1)
            if any(t.name.lower() == pending_test.name.lower() for t in tests):
                raise PfError(lineno, f'test {pending_test.name} defined twice')
            tests.append(pending_test)
            pending_test = None
        elif module_name is None:
            mm = MODULE_RE.match(line)
            if mm and mm.group(1).lower() not in ('procedure', 'subroutine', 'function'):
                module_name = mm.group(1)
                if module_name.lower() != base.lower():
                    raise PfError(lineno, f'module {module_name} must be named after the file, '
                                          f'i.e. `module {base}` (pFUnit requires it)')
        out.append(line)

    if pending_test:
        raise PfError(pending_test.lineno, '@test without a following subroutine')
    if pending_fixture:
        raise PfError(pending_fixture[1], f'@{pending_fixture[0]} without a following subroutine')
    if module_name is None:
        raise PfError(1, f'no `module {base}` found: pfunit_lite needs the tests in a module '
                         'named after the file')

    # ---- the runner program ----
    prog = []
    prog.append('program pfunit_lite_main')
    prog.append('   use funit, only: funit_run_test, funit_skip_test, funit_finish')
    plain = [t.name for t in tests if not t.disabled and not (t.ifdef or t.ifndef)]
    plain += [n for n in (before, after) if n]
    prog.extend(split_statement('   ', f'use {module_name}, only: ' + ', '.join(plain)
                                if plain else f'use {module_name}, only:'))
    for t in tests:
        if not t.disabled and (t.ifdef or t.ifndef):
            prog.extend(guard_open(t))
            prog.append(f'   use {module_name}, only: {t.name}')
            prog.extend(guard_close(t))
    prog.append('   implicit none')
    prog.append('')
    for t in tests:
        label = fortran_string(f'{base}.{t.name}')
        prog.extend(guard_open(t))
        if t.disabled:
            prog.append(f'   call funit_skip_test({label})')
        else:
            call = f'call funit_run_test({label}, {t.name}'
            if before:
                call += f', before={before}'
            if after:
                call += f', after={after}'
            prog.extend(split_statement('   ', call + ')'))
        prog.extend(guard_close(t))
    prog.append('')
    prog.append('   if (.not. funit_finish()) error stop 1')
    prog.append('end program pfunit_lite_main')

    out.append('')
    if line_directives:
        out.append(f'#line {len(out) + 2} {cpp_string(os.path.abspath(out_path))}')
    out.extend(prog)

    text = '\n'.join(out) + '\n'
    if out_path == '-':
        sys.stdout.write(text)
    else:
        with open(out_path, 'w', encoding='latin-1') as fh:
            fh.write(text)


def guard_open(test):
    lines = []
    if test.ifdef:
        lines.append(f'#ifdef {test.ifdef}')
    if test.ifndef:
        lines.append(f'#ifndef {test.ifndef}')
    return lines


def guard_close(test):
    return ['#endif'] * ((1 if test.ifdef else 0) + (1 if test.ifndef else 0))


def main(argv=None):
    parser = argparse.ArgumentParser(
        description='Translate a pFUnit 4 .pf suite into a plain Fortran test program '
                    '(pfunit_lite).')
    parser.add_argument('input', help='the .pf file')
    parser.add_argument('-o', '--output', default='-',
                        help='the Fortran file to write (default: standard output)')
    parser.add_argument('--no-line-directives', action='store_true',
                        help='omit #line directives (the #ifdef of @test(ifdef=) remain)')
    args = parser.parse_args(argv)
    try:
        translate(args.input, args.output, line_directives=not args.no_line_directives)
    except PfError as err:
        sys.stderr.write(f'{args.input}:{err.lineno}: error: {err.message}\n')
        return 2
    except OSError as err:
        sys.stderr.write(f'pf2f90.py: error: {err}\n')
        return 2
    return 0


if __name__ == '__main__':
    sys.exit(main())
