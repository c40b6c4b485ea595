// One WebSocket to ddsimp-server's /ws, kept open: the handshake (Hello, Welcome, Auth), a
// keep-alive Ping, and reconnecting with a growing delay whenever the server goes away.
import { decodeFrame, encodeFrame, enumValues, FrameError, PROTOCOL_VERSION } from './protocol.js';

const ClientKind = enumValues('ClientKind');
const ErrorCode = enumValues('Error.Code');
// The capabilities this page uses. meshopt-codec: levels arrive through meshoptimizer's codecs,
// about 1.5-2x smaller than raw, which matters on the links a browser is usually on (see README,
// "Is meshoptimizer's codec worth it?"); decoding is meshoptimizer's own WebAssembly decoder.
// session-keys: a session joined with ?key= is private to those who know the key. previews: the
// server sends a stand-in at once while it computes the exact level.
const CAPABILITIES = ['meshopt-codec', 'progressive', 'sessions', 'session-keys', 'previews'];
const RETRY_SECONDS = [1, 2, 4, 8, 10];
const PING_SECONDS = 30;

export class ServerConnection {
  // handlers: onReady(welcome), onMessage(name, message), onStatus(state, text)
  constructor(url, { token, handlers }) {
    this.url = url;
    this.token = token;
    this.handlers = handlers;
    this.ws = null;
    this.ready = false;
    this.attempt = 0;
    this.fatal = null; // set when retrying cannot help (a wrong token)
  }

  connect() {
    clearTimeout(this.retryTimer);
    this.ready = false;
    this.handlers.onStatus('connecting', `Connecting to ${this.url} …`);
    let ws;
    try {
      ws = new WebSocket(this.url);
    } catch (e) {
      this.handlers.onStatus('failed', `Cannot open ${this.url}: ${e.message}`);
      return;
    }
    ws.binaryType = 'arraybuffer';
    this.ws = ws;
    ws.onopen = () => {
      this.send('Hello', {
        protocol_version: PROTOCOL_VERSION,
        client_name: `ddsimp web (${navigator.userAgent.split(' ').pop()})`,
        kind: ClientKind.DESKTOP,
        capabilities: CAPABILITIES,
      });
    };
    ws.onmessage = (event) => {
      if (ws !== this.ws) return;
      if (typeof event.data === 'string') return this.abandon('the server sent a text message');
      let frame;
      try {
        frame = decodeFrame(event.data);
      } catch (e) {
        if (e instanceof FrameError) return this.abandon(`a bad frame from the server: ${e.message}`);
        throw e;
      }
      this.onFrame(frame.name, frame.message);
    };
    ws.onclose = (event) => {
      if (ws !== this.ws) return;
      this.ws = null;
      this.ready = false;
      clearInterval(this.pingTimer);
      this.scheduleRetry(event);
    };
  }

  onFrame(name, m) {
    if (name === 'Welcome') {
      this.welcome = m;
      if (!m.auth_required) return this.becomeReady();
      if (!this.token) {
        this.fatal = 'This server needs a token: open the page as /?token=YOUR_TOKEN';
        return this.abandon(this.fatal);
      }
      return this.send('Auth', { token: this.token });
    }
    if (name === 'AuthOk') return this.becomeReady();
    if (name === 'Error' && m.code === ErrorCode.UNAUTHENTICATED) {
      this.fatal = this.token
        ? `The server refused the token (${m.message}); check ?token=`
        : `The server refused this page: ${m.message}`;
      return this.abandon(this.fatal);
    }
    if (name === 'Ping') return this.send('Pong', { nonce: m.nonce });
    if (name === 'Pong') return;
    this.handlers.onMessage(name, m);
  }

  becomeReady() {
    this.ready = true;
    this.attempt = 0;
    clearInterval(this.pingTimer);
    this.pingTimer = setInterval(() => this.send('Ping', { nonce: Date.now() }), PING_SECONDS * 1000);
    this.handlers.onStatus('connected', `Connected to ${this.welcome.server_name || 'ddsimp-server'}`);
    this.handlers.onReady(this.welcome);
  }

  send(name, fields) {
    if (!this.ws || this.ws.readyState !== WebSocket.OPEN) return false;
    this.ws.send(encodeFrame(name, fields));
    return true;
  }

  // Closes on a protocol problem; the close handler reports and retries (unless fatal).
  abandon(why) {
    this.lastProblem = why;
    this.ws?.close();
  }

  scheduleRetry(event) {
    if (this.fatal) {
      this.handlers.onStatus('failed', this.fatal);
      return;
    }
    const seconds = RETRY_SECONDS[Math.min(this.attempt, RETRY_SECONDS.length - 1)];
    ++this.attempt;
    const why = this.lastProblem ??
      (event.code === 1006 ? 'no answer' : `closed (${event.code}${event.reason ? ': ' + event.reason : ''})`);
    this.lastProblem = undefined;
    this.handlers.onStatus(
      'unreachable',
      `Cannot reach the ddsimp server at ${this.url} (${why}); retrying in ${seconds} s`);
    this.retryTimer = setTimeout(() => this.connect(), seconds * 1000);
  }
}
