"""The shared secret (docs/protocol.md §4): the token file, the answer to a
participant's challenge and the participant's proof back, so that each end
shows the other it holds the secret."""

import hashlib
import hmac
import os
import stat

AUTH_TAG = b"railcosim-auth-v2"    # the master's (or connecting peer's) answer
PROOF_TAG = b"railcosim-proof-v4"  # the participant's proof in its HelloReply
MAX_TOKEN_FILE_BYTES = 4096
MIN_SECRET_CHARS = 16


def auth_answer(secret, participant, nonce):
    message = AUTH_TAG + participant.encode() + b"\0" + nonce
    return hmac.new(secret.encode(), message, hashlib.sha256).digest()


def auth_proof(secret, participant, hello_nonce, challenge_nonce):
    """What a participant with a secret puts in HelloReply.proof once the
    answer to its challenge was right: the hello's nonce and its own."""
    message = PROOF_TAG + participant.encode() + b"\0" + hello_nonce + challenge_nonce
    return hmac.new(secret.encode(), message, hashlib.sha256).digest()


def proof_failure(secret, participant, hello_nonce, challenge, proof):
    """Why a participant's answer to a hello that carried `hello_nonce` does
    not prove it holds `secret` ("" when it does): `challenge` is the nonce it
    sent (None: it asked none, so it has no secret), `proof` its
    HelloReply.proof."""
    if not challenge:
        return ("it asked no challenge, so it cannot prove that it holds the shared secret of "
                "--token-file (start it with the same --token-file, or find out what listens "
                "there)")
    if not hmac.compare_digest(proof, auth_proof(secret, participant, hello_nonce, challenge)):
        return ("it did not prove that it holds the shared secret of --token-file (its proof "
                "was %s): whatever listens there does not hold it"
                % ("wrong" if proof else "missing"))
    return ""


def read_token_file(path):
    """The secret in `path`, surrounding white space dropped. Raises
    ValueError naming the file when it is not a regular file (a FIFO is
    refused without waiting for a writer), others than its owner may read or
    change it (as ssh refuses a key), it holds more than MAX_TOKEN_FILE_BYTES
    or fewer than MIN_SECRET_CHARS characters; OSError when it cannot be
    opened."""
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | os.O_NOCTTY)
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise ValueError("the token file %s is not a regular file (a FIFO, device or "
                             "folder); put the secret in a plain file" % path)
        if st.st_mode & 0o077:
            raise ValueError("the token file %s has mode %04o: others than its owner may read "
                             "or change it; `chmod 600 %s`"
                             % (path, stat.S_IMODE(st.st_mode), path))
        if st.st_size > MAX_TOKEN_FILE_BYTES:
            raise ValueError("the token file %s holds %d bytes; a secret is at most %d"
                             % (path, st.st_size, MAX_TOKEN_FILE_BYTES))
        data = os.read(fd, MAX_TOKEN_FILE_BYTES + 1)
    finally:
        os.close(fd)
    if len(data) > MAX_TOKEN_FILE_BYTES:
        raise ValueError("the token file %s holds more than %d bytes; a secret is not that long"
                         % (path, MAX_TOKEN_FILE_BYTES))
    secret = data.decode("utf-8", "replace").strip(" \t\r\n")
    if len(secret) < MIN_SECRET_CHARS:
        raise ValueError("the token file %s must hold a secret of at least %d characters (e.g. "
                         "`(umask 077; head -c 32 /dev/urandom | base64 > %s)`)"
                         % (path, MIN_SECRET_CHARS, path))
    return secret
