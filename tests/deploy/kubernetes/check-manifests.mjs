// Usage: node check-manifests.mjs DIR. Checks the Kubernetes manifests of DIR the way
// `kubectl apply -k DIR` would, without a cluster (manifest_checks.mjs says what is checked).
// Exit status 0 when valid, 1 with one line per problem otherwise.
import { checkManifests } from "./manifest_checks.mjs";

const dir = process.argv[2];
if (dir === undefined) {
  console.error("usage: node check-manifests.mjs DIR");
  process.exit(2);
}
const errors = await checkManifests(dir);
for (const error of errors) console.error(`${dir}/${error}`);
if (errors.length > 0) process.exit(1);
console.log(`${dir}: valid`);
