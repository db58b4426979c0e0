"""What a directory holds, to tell that a run changed nothing in it (test_bad_decks.py,
test_hostile_geo.py). Standard library only."""
import hashlib
import os


def snapshot(root):
    """Every entry under root: relative name -> (kind, size, mtime, sha256). Links are not
    followed (kind 'link'); a file of 16 MiB or more (a sparse test file) is compared by
    size and time only, not read."""
    state = {}
    for base, dirs, files in os.walk(root):
        for name in dirs + files:
            full = os.path.join(base, name)
            st = os.lstat(full)
            digest = ""
            if os.path.isfile(full) and not os.path.islink(full) and st.st_size < 2**24:
                with open(full, "rb") as f:
                    digest = hashlib.sha256(f.read()).hexdigest()
            kind = ("link" if os.path.islink(full) else "dir" if os.path.isdir(full)
                    else "file")
            state[os.path.relpath(full, root)] = (kind, st.st_size, st.st_mtime_ns, digest)
    return state
