// ESLint for the page (a browser module) and its checks (Node).
import js from "@eslint/js";
import globals from "globals";

export default [
  { ignores: ["node_modules/"] },
  js.configs.recommended,
  {
    files: ["app.js"],
    languageOptions: { globals: globals.browser, sourceType: "module" },
  },
  {
    files: ["tests/**/*.mjs", "eslint.config.js"],
    // The checks run in Node and pass functions to the page, which run in the browser.
    languageOptions: { globals: { ...globals.node, ...globals.browser }, sourceType: "module" },
  },
];
