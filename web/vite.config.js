// Builds web/ into web/dist, which ddsimp-server serves at / (--web-dir). `npm run dev` serves
// the page with hot reload and forwards /ws to a server on localhost:7421.
import { defineConfig } from 'vite';

export default defineConfig({
  base: './',
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    target: 'es2020',
    chunkSizeWarningLimit: 1500,
  },
  server: {
    // The schema is read from ../protocol (see src/protocol.js).
    fs: { allow: ['..'] },
    proxy: { '/ws': { target: 'ws://localhost:7421', ws: true } },
  },
});
