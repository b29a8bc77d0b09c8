// The viewer page is built into the CMake build folder (BUILD/web), which the station serves.
// HYDRA_MULTI_WEB_OUT is set by CMake; `npm run build` alone writes dist/.
import { defineConfig } from "vite";

export default defineConfig({
  base: "./",
  build: {
    outDir: process.env.HYDRA_MULTI_WEB_OUT ?? "dist",
    emptyOutDir: true,
    chunkSizeWarningLimit: 1500,
  },
});
