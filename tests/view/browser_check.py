#!/usr/bin/env python3
"""Headless Chromium renders the page `mbx view` writes for a simulated arm.

usage: browser_check.py <mbx> <samples dir> <work dir>

The five-axis arm is simulated for 3 s (its motion program), `mbx view`
writes view.html beside the trajectory, Chromium opens it from a file:// URL
with no network, and two checks must hold: the page's own status line says it
posed all five bodies over every sample and drew the model, and the
screenshot, decoded here independently of the page, shows it (enough pixels
unlike the background). Exit 77 (skipped) where Chromium is not installed.
"""
import os
import shutil
import struct
import subprocess
import sys
import zlib

BACKGROUND = (0xF4, 0xF4, 0xF4)


def read_png(path):
    """Width, height and rows of RGB(A) tuples of an 8-bit PNG (no library)."""
    data = open(path, 'rb').read()
    assert data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
    pos, idat, width = 8, b'', 0
    while pos < len(data):
        length, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b'IHDR':
            width, height, depth, color = struct.unpack('>IIBB', body[:10])
            assert depth == 8 and color in (2, 6), 'unexpected PNG format %d/%d' % (depth, color)
            channels = 3 if color == 2 else 4
        elif kind == b'IDAT':
            idat += body
        pos += 12 + length
    raw, stride = zlib.decompress(idat), width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - channels] if x >= channels else 0
            b = previous[x]
            c = previous[x - channels] if x >= channels else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        previous = line
    return width, height, channels, rows


def main():
    mbx, samples, work = sys.argv[1:4]
    chromium = shutil.which('chromium') or shutil.which('chromium-browser')
    if not chromium:
        print('chromium is not installed: skipped')
        return 77
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    arm = [os.path.join(samples, 'five_axis_arm', 'five_axis_arm.xml'),
           '--shapes', os.path.join(samples, 'five_axis_arm', 'five_axis_arm_a.wrl'),
           '--drives', os.path.join(samples, 'mechatronics', 'five_axis_arm_drives.xml')]
    subprocess.run([mbx, 'simulate'] + arm + ['--stop-time', '3', '-o', work], check=True)
    subprocess.run([mbx, 'view'] + arm + ['-o', work], check=True)
    rows = sum(1 for _ in open(os.path.join(work, 'trajectory.csv'))) - 1
    page = 'file://' + os.path.abspath(os.path.join(work, 'view.html'))
    flags = [chromium, '--headless', '--no-sandbox', '--use-gl=swiftshader', '--enable-unsafe-swiftshader',
             '--window-size=800,600', '--virtual-time-budget=4000', '--user-data-dir=' + os.path.join(work, 'profile')]
    dom = subprocess.run(flags + ['--dump-dom', page], capture_output=True, text=True, timeout=240).stdout
    start = dom.find('id="mbx-status"')
    status = dom[dom.find('>', start) + 1:dom.find('</div>', start)] if start >= 0 else '(no status element)'
    print('page status:', status)
    fields = dict(item.split('=') for item in status.split() if '=' in item)
    ok = fields.get('nodes') == '5' and fields.get('frames') == str(rows) and float(fields.get('drawn', 0)) > 0.01
    shot = os.path.join(work, 'view.png')
    subprocess.run(flags + ['--screenshot=' + shot, page], capture_output=True, timeout=240)
    width, height, channels, pixels = read_png(shot)
    model = sum(1 for line in pixels for x in range(0, width * channels, channels)
                if sum(abs(line[x + k] - BACKGROUND[k]) for k in range(3)) > 24)
    share = model / float(width * height)
    print('screenshot %s: %dx%d, %.2f %% of the pixels show the model' % (shot, width, height, 100 * share))
    ok = ok and share > 0.01
    if not ok:
        print('FAILED: expected nodes=5 frames=%d drawn>0.01 and a screenshot with >1 %% model pixels' % rows)
        return 1
    # The default hulls, shown through view.html#collision: every moving
    # part's hull found in the scene, and more of the screen covered (the
    # hulls wrap the meshes, semi-transparent) than without them.
    subprocess.run([mbx, 'view'] + arm + ['--collision', 'hulls', '-o', work], check=True)
    dom = subprocess.run(flags + ['--dump-dom', page + '#collision'], capture_output=True, text=True, timeout=240).stdout
    start = dom.find('id="mbx-status"')
    status = dom[dom.find('>', start) + 1:dom.find('</div>', start)] if start >= 0 else '(no status element)'
    print('page status with collision shapes shown:', status)
    shown = dict(item.split('=') for item in status.split() if '=' in item)
    if not (shown.get('nodes') == '5' and shown.get('collision') == '5' and
            float(shown.get('drawn', 0)) > float(fields['drawn'])):
        print('FAILED: expected nodes=5 collision=5 and drawn above %s' % fields['drawn'])
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
