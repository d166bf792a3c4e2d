"""inspect: it reads only, and says what is wrong with a file in one line."""

from hostile import Case, write

CASES = [
    Case(
        "inspect a truncated video",
        ("inspect", "t_256x192_yuv420p.yuv"),
        1,
        r"t_256x192_yuv420p.yuv: 100000 bytes is not a whole number of 256x192 yuv420p frames",
        write("t_256x192_yuv420p.yuv", bytes(100000)),
    ),
    Case(
        "inspect a camera block cut short",
        ("inspect", "c.txt", "--as", "cameras"),
        2,
        r"c.txt:1: cam1: camera block has 3 numbers, 23 needed",
        write("c.txt", "cam1\n1 0 0\n"),
    ),
    Case("inspect a missing file", ("inspect", "nothere.cfg"), 2, r"nothere.cfg: no such file"),
    Case(
        "inspect a configuration value of the wrong type",
        ("inspect", "s.cfg", "--as", "vsrs"),
        2,
        r"s.cfg:1: Precision: 'half' is not an integer",
        write("s.cfg", "Precision half\n"),
    ),
]
