#!/usr/bin/env python3
"""Generate filmsplat's embedded bitmap font (src/image/font/dejavu_sans.bin) from DejaVu Sans.

Needs Pillow with FreeType and libraqm (`pip install pillow`); run from the repository root:

    python3 tools/gen_font.py [/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf]

What it stores: one "master" coverage bitmap per glyph at MASTER_PX pixels per em. Each bitmap is
rendered by FreeType at OVERSAMPLE x MASTER_PX and box-averaged down, so hinting has no visible
effect and the coverage is close to the exact area coverage of the outline. The renderer
(src/image/text.rs) area-resamples these masters to any size at draw time, with sub-pixel pen
positions. Advances and pair kerning (GPOS, via raqm) are stored in font units, so layout is exact
at every size.

File layout (all little-endian):
    magic            8 bytes  b"FSFONT01"
    units_per_em     u16      (2048 for DejaVu)
    master_px        u16      pixels per em of the stored bitmaps
    ascender         i16      font units, y up (hhea)
    descender        i16      font units, y up (negative)
    cap_height       i16      font units (top of 'H')
    x_height         i16      font units (top of 'x')
    ink_top          i16      font units: highest ink of any stored glyph
    ink_bottom       i16      font units: lowest ink of any stored glyph (negative)
    n_glyphs         u16
    n_kern           u16
    glyphs           n_glyphs x 24 bytes, sorted by code point:
        code u32, advance u16 (font units), left i16, top i16 (master px; bitmap's top-left
        relative to the pen on the baseline, y down), width u16, height u16, pad u16,
        data_offset u32, data_len u32 (into the RLE stream)
    kern pairs       n_kern x 6 bytes, sorted: left glyph index u16, right index u16, value i16
    RLE stream       coverage bytes, row-major, per glyph. Token t:
                       0..=63   -> t+1 literal bytes follow
                       64..=127 -> run of (t-63) zero bytes
                       128..=255-> run of (t-127) 255 bytes
"""

import struct
import sys

from PIL import Image, ImageDraw, ImageFont

FONT = sys.argv[1] if len(sys.argv) > 1 else "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
OUT = "src/image/font/dejavu_sans.bin"
MASTER_PX = 64
OVERSAMPLE = 4
UNITS_PER_EM = 2048

# ASCII printable plus a few symbols needed for axis labels and units.
EXTRA = [
    0x00B0,  # degree sign
    0x00B5,  # micro sign
    0x03BB,  # greek small lambda
    0x03B8,  # greek small theta
    0x2013,  # en dash
    0x2212,  # minus sign
    0x00D7,  # multiplication sign
    0x00B1,  # plus-minus sign
    0x00B2,  # superscript two
    0x00B3,  # superscript three
    0x00B7,  # middle dot
    0x0394,  # greek capital delta
    0x00C5,  # A with ring (angstrom)
]
CODES = sorted(list(range(32, 127)) + EXTRA)


def rle(data):
    out = bytearray()
    i, n = 0, len(data)
    lit = bytearray()

    def flush():
        nonlocal lit
        while lit:
            chunk = lit[:64]
            out.append(len(chunk) - 1)
            out.extend(chunk)
            lit = lit[64:]

    while i < n:
        v = data[i]
        if v in (0, 255):
            j = i
            limit = 64 if v == 0 else 128
            while j < n and data[j] == v and j - i < limit:
                j += 1
            run = j - i
            if run >= 2 or not lit:
                flush()
                out.append((63 + run) if v == 0 else (127 + run))
                i = j
                continue
        lit.append(v)
        i += 1
    flush()
    return bytes(out)


def unrle(buf, n):
    out = bytearray()
    i = 0
    while len(out) < n:
        t = buf[i]
        i += 1
        if t < 64:
            out.extend(buf[i : i + t + 1])
            i += t + 1
        elif t < 128:
            out.extend(b"\0" * (t - 63))
        else:
            out.extend(b"\xff" * (t - 127))
    assert len(out) == n and i == len(buf)
    return bytes(out)


def main():
    hi = MASTER_PX * OVERSAMPLE
    render_font = ImageFont.truetype(FONT, hi, layout_engine=ImageFont.Layout.BASIC)
    units = ImageFont.truetype(FONT, UNITS_PER_EM, layout_engine=ImageFont.Layout.RAQM)
    ascender, descender_pos = units.getmetrics()

    def ink_top(ch):
        # getbbox with anchor 'ls' is relative to the baseline, y down.
        return -units.getbbox(ch, anchor="ls")[1]

    cap_height = ink_top("H")
    x_height = ink_top("x")

    # Canvas big enough for any glyph; origin on a multiple of OVERSAMPLE so the master grid
    # aligns with the pen position.
    cw, ch_ = 3 * hi, 3 * hi
    ox, oy = hi, 2 * hi
    glyphs = []
    stream = bytearray()
    ink_hi, ink_lo = 0, 0
    for code in CODES:
        c = chr(code)
        adv = units.getlength(c, features=["-liga", "-kern"])
        assert abs(adv - round(adv)) < 1e-6, (c, adv)
        img = Image.new("L", (cw, ch_), 0)
        ImageDraw.Draw(img).text((ox, oy), c, font=render_font, fill=255, anchor="ls")
        small = img.reduce(OVERSAMPLE)
        bbox = small.getbbox()
        if bbox is None:
            left = top = w = h = 0
            data = b""
        else:
            x0, y0, x1, y1 = bbox
            data = small.crop(bbox).tobytes()
            left, top, w, h = x0 - ox // OVERSAMPLE, y0 - oy // OVERSAMPLE, x1 - x0, y1 - y0
            assert x0 > 0 and y0 > 0 and x1 < cw // OVERSAMPLE and y1 < ch_ // OVERSAMPLE, c
            b = units.getbbox(c, anchor="ls")
            ink_hi = max(ink_hi, -b[1])
            ink_lo = min(ink_lo, -b[3])
        enc = rle(data)
        assert unrle(enc, len(data)) == data
        glyphs.append((code, int(round(adv)), left, top, w, h, len(stream), len(enc)))
        stream.extend(enc)

    kerns = []
    for i, a in enumerate(CODES):
        for j, b in enumerate(CODES):
            pair = chr(a) + chr(b)
            both = units.getlength(pair, features=["-liga"])
            k = both - glyphs[i][1] - glyphs[j][1]
            if abs(k) >= 0.5:
                kerns.append((i, j, int(round(k))))

    out = bytearray(b"FSFONT01")
    out += struct.pack(
        "<HHhhhhhhHH",
        UNITS_PER_EM,
        MASTER_PX,
        ascender,
        -descender_pos,
        cap_height,
        x_height,
        ink_hi,
        ink_lo,
        len(glyphs),
        len(kerns),
    )
    for code, adv, left, top, w, h, off, ln in glyphs:
        out += struct.pack("<IHhhHHHII", code, adv, left, top, w, h, 0, off, ln)
    for i, j, k in kerns:
        out += struct.pack("<HHh", i, j, k)
    out += stream
    with open(OUT, "wb") as f:
        f.write(out)
    raw = sum(g[4] * g[5] for g in glyphs)
    print(
        f"{OUT}: {len(glyphs)} glyphs, {len(kerns)} kern pairs, {len(out)} bytes "
        f"(bitmaps {raw} raw -> {len(stream)} RLE); ascender {ascender}, "
        f"cap {cap_height}, x {x_height}, ink {ink_hi}..{ink_lo}"
    )


if __name__ == "__main__":
    main()
