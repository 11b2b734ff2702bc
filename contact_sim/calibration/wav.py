"""WAV files read in blocks (bounded memory) and written, for the onset detector.

``open_wav(path)`` reads the RIFF header only (the ``fmt`` and ``data`` chunks, any other chunk
skipped): integer PCM of 8, 16, 24 or 32 bits and IEEE float of 32 or 64 bits, any number of
channels, WAVE_FORMAT_EXTENSIBLE included.  ``WavFile.read(start, stop)`` returns frames
``start:stop`` as floats in full-scale units (an (m, channels) array), so a recording of any length
is processed in blocks whose size the caller chooses.  ``write_wav`` writes test recordings.
"""
from dataclasses import dataclass

import numpy as np
from scipy.io import wavfile

from contact_sim.validation import InputError

PCM, IEEE_FLOAT, EXTENSIBLE = 1, 3, 0xFFFE
MAX_CHANNELS = 64        # channels of a recording, at most (a block of 2^19 frames: 268 MB)
MAX_RATE = 1e7           # Hz: a sample rate, at most


@dataclass(frozen=True)
class WavFile:
    """A WAV file's layout: sample ``rate`` (Hz), ``channels``, ``frames``, sample ``bits``,
    ``floating`` (IEEE float samples) and where its samples start (``offset``, bytes)."""

    path: str
    rate: float
    channels: int
    frames: int
    bits: int
    floating: bool
    offset: int

    def read(self, start, stop):
        """Frames ``start:stop`` as an (m, channels) float array, full scale 1."""
        start, stop = max(int(start), 0), min(int(stop), self.frames)
        if stop <= start:
            return np.zeros((0, self.channels))
        width = self.bits // 8
        block = width * self.channels
        with open(self.path, 'rb') as f:
            f.seek(self.offset + start * block)
            raw = np.frombuffer(f.read((stop - start) * block), dtype=np.uint8)
        raw = raw[:raw.size - raw.size % block]
        if self.floating:
            x = raw.view('<f4' if width == 4 else '<f8').astype(float)
        elif width == 1:
            x = (raw.astype(float) - 128.0) / 128.0
        elif width == 3:
            b = raw.reshape(-1, 3).astype(np.int32)
            v = b[:, 0] | (b[:, 1] << 8) | (b[:, 2] << 16)
            x = np.where(v >= 1 << 23, v - (1 << 24), v) / float(1 << 23)
        else:
            x = raw.view('<i2' if width == 2 else '<i4').astype(float) / float(1 << (self.bits - 1))
        return x.reshape(-1, self.channels)


def _refuse(path, reason):
    raise InputError('audio', str(path), '{n[audio]} = {value} cannot be read as WAV: {reason}',
                     value=repr(str(path)), reason=reason)


def open_wav(path):
    """The layout of the WAV file at ``path`` (a ``WavFile``); its header only is read.

    Raises
    ------
    InputError
        ``audio = 'path' cannot be read as WAV: ...`` for a missing file, a header cut off, an
        encoding other than integer PCM (8-32 bit) or IEEE float (32/64 bit), more than
        ``MAX_CHANNELS`` channels, or fewer than 16 frames.
    """
    try:
        f = open(path, 'rb')
    except OSError as error:
        _refuse(path, error.strerror or str(error))
    with f:
        head = f.read(12)
        if len(head) < 12 or head[:4] != b'RIFF' or head[8:12] != b'WAVE':
            _refuse(path, 'no RIFF/WAVE header')
        fmt = None
        while True:
            chunk = f.read(8)
            if len(chunk) < 8:
                _refuse(path, 'no data chunk' if fmt else 'no fmt chunk (header cut off)')
            cid, size = chunk[:4], int.from_bytes(chunk[4:], 'little')
            if cid == b'fmt ':
                body = f.read(size + (size & 1))
                if len(body) < 16:
                    _refuse(path, 'fmt chunk cut off')
                fmt = body
            elif cid == b'data':
                if fmt is None:
                    _refuse(path, 'data chunk before the fmt chunk')
                offset = f.tell()
                f.seek(0, 2)
                size = min(size, f.tell() - offset)    # a file cut off: what is there
                break
            else:
                f.seek(size + (size & 1), 1)
    tag = int.from_bytes(fmt[0:2], 'little')
    channels = int.from_bytes(fmt[2:4], 'little')
    rate = int.from_bytes(fmt[4:8], 'little')
    bits = int.from_bytes(fmt[14:16], 'little')
    if tag == EXTENSIBLE and len(fmt) >= 26:
        tag = int.from_bytes(fmt[24:26], 'little')
    floating = tag == IEEE_FLOAT
    if not ((tag == PCM and bits in (8, 16, 24, 32)) or (floating and bits in (32, 64))):
        _refuse(path, f'encoding {tag} with {bits} bits: allowed integer PCM of 8, 16, 24 or '
                      '32 bits or IEEE float of 32 or 64 bits')
    if not 1 <= channels <= MAX_CHANNELS or not 1 <= rate <= MAX_RATE:
        _refuse(path, f'{channels} channels at {rate} Hz: allowed 1 to {MAX_CHANNELS} channels '
                      f'at 1 Hz to {MAX_RATE:g} Hz')
    frames = size // (channels * bits // 8)
    if frames < 16:
        raise InputError('audio', str(path), '{n[audio]} = {value} holds %d samples: allowed a '
                         'recording of at least 16 samples' % frames, value=repr(str(path)))
    return WavFile(str(path), float(rate), channels, frames, bits, floating, offset)


def read_wav(path):
    """(sample rate Hz, all samples as a float array (n, channels), full scale 1)."""
    wav = open_wav(path)
    return wav.rate, wav.read(0, wav.frames)


def write_wav(path, samples, rate, bits=16):
    """Write float samples (n,) or (n, channels) in [-1, 1] as a WAV file: ``bits`` 16, 24 or
    32 (integer PCM) or 'float' (32-bit IEEE float).  24-bit is written by hand (scipy's writer
    has no 24-bit integer type)."""
    x = np.asarray(samples, dtype=float)
    if bits == 'float':
        wavfile.write(path, int(rate), x.astype(np.float32))
        return
    if bits == 16:
        wavfile.write(path, int(rate), np.round(x * 32767.0).astype(np.int16))
        return
    if bits == 32:
        wavfile.write(path, int(rate), np.round(x * 2147483647.0).astype(np.int32))
        return
    if bits != 24:
        raise ValueError(f'bits = {bits!r} is unknown: allowed 16, 24, 32 or float')
    channels = 1 if x.ndim == 1 else x.shape[1]
    ints = np.round(np.clip(x, -1.0, 1.0) * 8388607.0).astype('<i4').reshape(-1)
    raw = ints.view(np.uint8).reshape(-1, 4)[:, :3].tobytes()
    block = 3 * channels
    header = b''.join([
        b'RIFF', (36 + len(raw)).to_bytes(4, 'little'), b'WAVE',
        b'fmt ', (16).to_bytes(4, 'little'), (1).to_bytes(2, 'little'),
        channels.to_bytes(2, 'little'), int(rate).to_bytes(4, 'little'),
        (int(rate) * block).to_bytes(4, 'little'), block.to_bytes(2, 'little'),
        (24).to_bytes(2, 'little'), b'data', len(raw).to_bytes(4, 'little')])
    with open(path, 'wb') as f:
        f.write(header + raw)

