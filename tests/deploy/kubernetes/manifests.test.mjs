// The manifests of deploy/kubernetes pass the checks, and each kind of fault the checks exist
// for, planted in a copy of those manifests, is reported with the object and the cause.
import { test } from "node:test";
import assert from "node:assert/strict";
import { execFileSync, spawnSync } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import {
  checkFieldNames,
  checkKustomization,
  checkManifests,
  checkReferences,
  checkSchemas,
  loadManifests,
} from "./manifest_checks.mjs";

const here = path.dirname(new URL(import.meta.url).pathname);
const manifests = process.env.DDSIMP_MANIFESTS ?? path.join(here, "../../../deploy/kubernetes");

// A deep copy of the shipped manifests, and the first object of a kind in it.
const freshDocs = () => structuredClone(loadManifests(manifests).docs);
const objectOf = (docs, kind) => docs.find((d) => d.object.kind === kind).object;
const containerOf = (docs) => objectOf(docs, "Deployment").spec.template.spec.containers[0];

function assertReports(errors, ...fragments) {
  assert.ok(errors.length > 0, "expected a problem to be reported, got none");
  const text = errors.join("\n");
  for (const fragment of fragments) assert.ok(text.includes(fragment), `'${fragment}' not in:\n${text}`);
}

test("the shipped manifests are valid and complete", async () => {
  assert.deepEqual(await checkManifests(manifests), []);
  const kinds = freshDocs().map((d) => d.object.kind).sort();
  assert.deepEqual(kinds, ["ConfigMap", "Deployment", "Kustomization", "PersistentVolumeClaim", "Secret", "Service"]);
});

test("a field of the wrong type breaks the schema", async () => {
  const docs = freshDocs();
  containerOf(docs).ports[0].containerPort = "7420";
  assertReports(await checkSchemas(docs), "deployment.yaml", "containerPort", "integer");
});

test("a missing required field breaks the schema", async () => {
  const docs = freshDocs();
  delete objectOf(docs, "Deployment").spec.selector;
  assertReports(await checkSchemas(docs), "deployment.yaml", "selector");
});

test("an apiVersion the API does not serve is reported", async () => {
  const docs = freshDocs();
  objectOf(docs, "Service").apiVersion = "v2";
  assertReports(await checkSchemas(docs), "service.yaml", "unknown apiVersion/kind v2/Service");
});

test("a misspelt field, which the schema lets through, is caught by the types", async () => {
  const docs = freshDocs();
  const container = containerOf(docs);
  container.resourses = container.resources;
  delete container.resources;
  assert.deepEqual(await checkSchemas(docs), []);
  assertReports(await checkFieldNames(docs), "deployment.yaml", "resourses");
});

test("the kustomization lists every manifest and nothing else", () => {
  const docs = freshDocs();
  const kustomization = objectOf(docs, "Kustomization");
  kustomization.resources = kustomization.resources.filter((r) => r !== "pvc.yaml").concat("ingress.yaml");
  assertReports(checkKustomization(docs), "does not list 'pvc.yaml'", "lists 'ingress.yaml', which holds no manifest");
});

test("a selector that misses the pod template is reported", () => {
  const docs = freshDocs();
  objectOf(docs, "Deployment").spec.selector.matchLabels["app.kubernetes.io/name"] = "ddsimp";
  assertReports(checkReferences(docs), "Deployment ddsimp-server: selector does not match");
  const other = freshDocs();
  objectOf(other, "Service").spec.selector = { app: "ddsimp" };
  assertReports(checkReferences(other), "Service ddsimp-server: selector matches no pod template");
});

test("ports named by probes, the Service and the scrape annotation must exist", () => {
  const docs = freshDocs();
  containerOf(docs).livenessProbe.httpGet.port = "health";
  objectOf(docs, "Service").spec.ports[0].targetPort = "grpc";
  objectOf(docs, "Deployment").spec.template.metadata.annotations["prometheus.io/port"] = "9090";
  assertReports(checkReferences(docs), "livenessProbe uses port 'health'", "targets 'grpc'", "prometheus.io/port uses port '9090'");
});

test("ConfigMaps, Secrets, keys, claims and volumes referred to must exist", () => {
  const docs = freshDocs();
  const deployment = objectOf(docs, "Deployment");
  const container = containerOf(docs);
  container.envFrom[0].configMapRef.name = "ddsimp-settings";
  container.env[0].valueFrom.secretKeyRef.key = "password";
  container.volumeMounts.push({ name: "scratch", mountPath: "/scratch" });
  const volumes = deployment.spec.template.spec.volumes;
  volumes.find((v) => v.persistentVolumeClaim).persistentVolumeClaim.claimName = "ddsimp-store";
  volumes.find((v) => v.configMap).configMap.items[0].key = "server.conf";
  assertReports(
    checkReferences(docs),
    "envFrom needs ConfigMap 'ddsimp-settings'",
    "DDSIMP_TOKEN needs key 'password' of Secret 'ddsimp-server'",
    "mounts volume 'scratch'",
    "needs PersistentVolumeClaim 'ddsimp-store'",
    "needs key 'server.conf' of ConfigMap 'ddsimp-server'",
  );
});

test("the command fails on a broken copy, naming the file, and passes on the original", () => {
  const command = path.join(here, "check-manifests.mjs");
  execFileSync(process.execPath, [command, manifests]);
  const copy = fs.mkdtempSync(path.join(os.tmpdir(), "ddsimp-manifests-"));
  try {
    fs.cpSync(manifests, copy, { recursive: true });
    const service = path.join(copy, "service.yaml");
    fs.writeFileSync(service, fs.readFileSync(service, "utf8").replace("targetPort: http", "targetPort: web"));
    const run = spawnSync(process.execPath, [command, copy], { encoding: "utf8" });
    assert.equal(run.status, 1);
    assert.ok(run.stderr.includes("service.yaml: Service ddsimp-server: port 'http' targets 'web'"), run.stderr);
  } finally {
    fs.rmSync(copy, { recursive: true, force: true });
  }
});
