"""Saving a figure into an output folder without writing through what is there.

The figure goes to a new file made under an unguessable name in the same
folder (O_EXCL: never a link or a file planted there), then replaces the
final name (os.replace: a link at that name is replaced, never followed).
A failure to write is an error that names the file.
"""
import os
import tempfile


def save_figure(fig, path, **options):
    path = os.fspath(path)
    folder = os.path.dirname(path) or "."
    descriptor, temporary = tempfile.mkstemp(prefix=os.path.basename(path) + ".partial-", dir=folder)
    # mkstemp makes it owner-only; a figure is as readable as any file made here.
    mask = os.umask(0)
    os.umask(mask)
    try:
        os.fchmod(descriptor, 0o666 & ~mask)
        with os.fdopen(descriptor, "wb") as out:
            fig.savefig(out, format=os.path.splitext(path)[1].lstrip(".") or "png", **options)
        os.replace(temporary, path)
    except BaseException:
        try:
            os.unlink(temporary)
        except FileNotFoundError:
            pass
        raise
