"""How the add-on's messages name Blender's kinds and show numbers, so that every report reads alike."""

from __future__ import annotations


def with_article(kind: str) -> str:
    """A Blender type name as words with their article: "POINT" -> "a point", "EMPTY" -> "an empty"."""
    words = kind.lower().replace("_", " ")
    return f"{'an' if words[:1] in tuple('aeiou') else 'a'} {words}"


def short_number(value: float) -> str:
    """A number in at most four significant digits: a value typed as 1e38 reads 1e+38, not 39 digits."""
    return f"{value:.4g}"


def short_bytes(count: float) -> str:
    """An amount of memory in three significant digits and the unit that suits it: "184 KB", "4.1 GB"."""
    for unit in ("bytes", "KB", "MB", "GB"):
        if count < 1000:
            return f"{count:.3g} {unit}"
        count /= 1000
    return f"{count:,.3g} TB"


def sentence_start(text: str) -> str:
    """``text`` opening a sentence: its first letter a capital, the rest untouched (str.capitalize
    would lower a file name within it: 'IMG_Left.JPG')."""
    return text[:1].upper() + text[1:]
