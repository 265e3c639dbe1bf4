"""What `Trajectory.view` returns, so that Jupyter shows the viewer instead of printing
its HTML: the page as text that displays as an inline viewer, or a written file that
displays as a link (a notebook then keeps a few hundred bytes instead of the page's
0.7–1.4 MB)."""

from __future__ import annotations

import html
import os


class ViewerPage(str):
    """The viewer page's HTML (a `str`); in Jupyter it displays as the viewer, inline in an
    iframe."""

    def _repr_html_(self) -> str:
        doc = html.escape(str(self), quote=True)
        return f'<iframe srcdoc="{doc}" style="width: 100%; height: 680px; border: 1px solid #ccc" sandbox="allow-scripts"></iframe>'

    def __repr__(self) -> str:
        return f"<ellipsoid viewer page, {len(self) / 1e6:.2f} MB of HTML; str(page) is the text>"


class ViewerFile(os.PathLike):  # type: ignore[type-arg]
    """A viewer page written to `path`; in Jupyter it displays as an iframe of that file
    (and a link to it), which a notebook stores as a few hundred bytes."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = os.fspath(path)

    def __fspath__(self) -> str:
        return self.path

    def _repr_html_(self) -> str:
        src = html.escape(self.path, quote=True)
        return (
            f'<iframe src="{src}" style="width: 100%; height: 680px; border: 1px solid #ccc"></iframe>'
            f'<p><a href="{src}" target="_blank">{src}</a></p>'
        )

    def __repr__(self) -> str:
        return f"<ellipsoid viewer page {self.path!r}>"
