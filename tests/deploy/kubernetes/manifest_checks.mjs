// What `kubectl apply -k deploy/kubernetes` would reject, checked without a cluster:
//  - the kustomization lists exactly the manifests of the folder;
//  - every object against the Kubernetes API's OpenAPI schema (kubernetes-models' validators:
//    required fields, types, formats);
//  - every object against the API's TypeScript types with excess-property checks, which catch a
//    misspelt field the schema lets through (the API server drops unknown fields silently);
//  - the references between objects that the API server does not check but the pod needs to
//    start: selectors, named ports, ConfigMaps, Secrets and their keys, claims, volume mounts.
// Each check returns a list of messages "file: what is wrong"; an empty list means valid.
import fs from "node:fs";
import path from "node:path";
import { parseAllDocuments } from "yaml";
import ts from "typescript";

const here = path.dirname(new URL(import.meta.url).pathname);

// Reads every YAML document of `dir`: [{file, object}], plus parse errors.
export function loadManifests(dir) {
  const docs = [];
  const errors = [];
  for (const file of fs.readdirSync(dir).filter((f) => /\.ya?ml$/.test(f)).sort()) {
    for (const doc of parseAllDocuments(fs.readFileSync(path.join(dir, file), "utf8"))) {
      if (doc.errors.length > 0) {
        errors.push(`${file}: ${doc.errors[0].message}`);
      } else if (doc.contents !== null) {
        docs.push({ file, object: doc.toJS() });
      }
    }
  }
  return { docs, errors };
}

const isKustomization = (object) => object.kind === "Kustomization";

export function checkKustomization(docs) {
  const kustomizations = docs.filter((d) => isKustomization(d.object));
  if (kustomizations.length !== 1) {
    return [`expected one Kustomization, found ${kustomizations.length}`];
  }
  const { file, object } = kustomizations[0];
  const errors = [];
  const known = new Set(["apiVersion", "kind", "resources"]);
  for (const key of Object.keys(object)) {
    if (!known.has(key)) errors.push(`${file}: unexpected field '${key}'`);
  }
  if (object.apiVersion !== "kustomize.config.k8s.io/v1beta1") {
    errors.push(`${file}: apiVersion must be kustomize.config.k8s.io/v1beta1`);
  }
  const listed = new Set(object.resources ?? []);
  const present = new Set(docs.filter((d) => !isKustomization(d.object)).map((d) => d.file));
  for (const name of listed) {
    if (!present.has(name)) errors.push(`${file}: lists '${name}', which holds no manifest`);
  }
  for (const name of present) {
    if (!listed.has(name)) errors.push(`${file}: does not list '${name}'`);
  }
  return errors;
}

// The model class of an object's apiVersion and kind, e.g. apps/v1 Deployment, from the
// "kubernetes-models/apps/v1" module (the core group is "v1"); null when the API has no such kind.
const modelModule = ({ apiVersion }) => `kubernetes-models/${apiVersion}`;

async function modelOf(object) {
  if (typeof object.apiVersion !== "string" || typeof object.kind !== "string") return null;
  try {
    const model = (await import(modelModule(object)))[object.kind];
    return typeof model === "function" && typeof model.prototype.validate === "function" ? model : null;
  } catch {
    return null;
  }
}

// The API objects of `docs` (not the Kustomization) with their model classes.
async function apiObjects(docs) {
  const objects = [];
  for (const doc of docs.filter((d) => !isKustomization(d.object))) {
    objects.push({ ...doc, Model: await modelOf(doc.object) });
  }
  return objects;
}

export async function checkSchemas(docs) {
  const errors = [];
  for (const { file, object, Model } of await apiObjects(docs)) {
    if (Model === null) {
      errors.push(`${file}: unknown apiVersion/kind ${object.apiVersion}/${object.kind}`);
      continue;
    }
    try {
      new Model(object).validate();
    } catch (e) {
      for (const error of e.errors ?? [{ instancePath: "", message: e.message }]) {
        errors.push(`${file}: ${object.kind}${error.instancePath} ${error.message}`);
      }
    }
  }
  return errors;
}

// Writes each object as a typed literal, `const o: IDeployment = {...}`, and lets the TypeScript
// compiler check it; diagnostics are mapped back to the manifest they came from.
export async function checkFieldNames(docs) {
  const objects = (await apiObjects(docs)).filter((d) => d.Model !== null);
  const lines = [];
  const origin = [];
  objects.forEach(({ object }, i) => {
    lines.push(`import type { I${object.kind} as T${i} } from "${modelModule(object)}";`);
    origin.push(null);
  });
  objects.forEach(({ file, object }, i) => {
    for (const line of `export const o${i}: T${i} = ${JSON.stringify(object, null, 1)};`.split("\n")) {
      lines.push(line);
      origin.push(file);
    }
  });
  // Inside this folder so that node_modules resolves; removed afterwards.
  const scratch = fs.mkdtempSync(path.join(here, ".typecheck-"));
  const source = path.join(scratch, "manifests.ts");
  try {
    fs.writeFileSync(source, lines.join("\n"));
    const program = ts.createProgram([source], {
      strict: true,
      noEmit: true,
      module: ts.ModuleKind.NodeNext,
      moduleResolution: ts.ModuleResolutionKind.NodeNext,
      types: [],
    });
    return ts.getPreEmitDiagnostics(program).map((d) => {
      const text = ts.flattenDiagnosticMessageText(d.messageText, " ");
      if (d.file === undefined || d.file.fileName !== source) return `type check: ${text}`;
      const { line } = d.file.getLineAndCharacterOfPosition(d.start);
      return `${origin[line] ?? "manifests"}: ${text}`;
    });
  } finally {
    fs.rmSync(scratch, { recursive: true, force: true });
  }
}

const matches = (selector, labels) =>
  Object.entries(selector ?? {}).every(([key, value]) => labels?.[key] === value);

export function checkReferences(docs) {
  const errors = [];
  const named = (kind) =>
    new Map(docs.filter((d) => d.object.kind === kind).map((d) => [d.object.metadata?.name, d.object]));
  const configMaps = named("ConfigMap");
  const secrets = named("Secret");
  const claims = named("PersistentVolumeClaim");
  const secretKeys = (s) => new Set([...Object.keys(s.data ?? {}), ...Object.keys(s.stringData ?? {})]);
  const mapKeys = (m) => new Set([...Object.keys(m.data ?? {}), ...Object.keys(m.binaryData ?? {})]);

  const workloads = docs.filter((d) => ["Deployment", "StatefulSet"].includes(d.object.kind));
  for (const { file, object } of workloads) {
    const where = `${file}: ${object.kind} ${object.metadata?.name}`;
    const template = object.spec?.template ?? {};
    const podLabels = template.metadata?.labels ?? {};
    if (!matches(object.spec?.selector?.matchLabels, podLabels)) {
      errors.push(`${where}: selector does not match the pod template's labels`);
    }
    const pod = template.spec ?? {};
    const volumes = new Map((pod.volumes ?? []).map((v) => [v.name, v]));
    for (const volume of volumes.values()) {
      if (volume.configMap) {
        const map = configMaps.get(volume.configMap.name);
        if (!map) errors.push(`${where}: volume '${volume.name}' needs ConfigMap '${volume.configMap.name}'`);
        for (const item of volume.configMap.items ?? []) {
          if (map && !mapKeys(map).has(item.key)) {
            errors.push(`${where}: volume '${volume.name}' needs key '${item.key}' of ConfigMap '${volume.configMap.name}'`);
          }
        }
      }
      if (volume.secret && !secrets.has(volume.secret.secretName)) {
        errors.push(`${where}: volume '${volume.name}' needs Secret '${volume.secret.secretName}'`);
      }
      if (volume.persistentVolumeClaim && !claims.has(volume.persistentVolumeClaim.claimName)) {
        errors.push(`${where}: volume '${volume.name}' needs PersistentVolumeClaim '${volume.persistentVolumeClaim.claimName}'`);
      }
    }
    for (const container of [...(pod.initContainers ?? []), ...(pod.containers ?? [])]) {
      const at = `${where} container '${container.name}'`;
      const portNames = new Set((container.ports ?? []).map((p) => p.name).filter(Boolean));
      const portNumbers = new Set((container.ports ?? []).map((p) => p.containerPort));
      const checkPort = (port, what) => {
        const known = typeof port === "string" ? portNames.has(port) : portNumbers.has(port);
        if (!known) errors.push(`${at}: ${what} uses port '${port}', which the container does not declare`);
      };
      for (const probe of ["readinessProbe", "livenessProbe", "startupProbe"]) {
        const action = container[probe]?.httpGet ?? container[probe]?.tcpSocket;
        if (action) checkPort(action.port, probe);
      }
      const scrapePort = template.metadata?.annotations?.["prometheus.io/port"];
      if (scrapePort !== undefined) checkPort(Number(scrapePort), "annotation prometheus.io/port");
      for (const source of container.envFrom ?? []) {
        if (source.configMapRef && !configMaps.has(source.configMapRef.name)) {
          errors.push(`${at}: envFrom needs ConfigMap '${source.configMapRef.name}'`);
        }
        if (source.secretRef && !secrets.has(source.secretRef.name)) {
          errors.push(`${at}: envFrom needs Secret '${source.secretRef.name}'`);
        }
      }
      for (const variable of container.env ?? []) {
        const fromSecret = variable.valueFrom?.secretKeyRef;
        const fromMap = variable.valueFrom?.configMapKeyRef;
        if (fromSecret && !(secrets.has(fromSecret.name) && secretKeys(secrets.get(fromSecret.name)).has(fromSecret.key))) {
          errors.push(`${at}: ${variable.name} needs key '${fromSecret.key}' of Secret '${fromSecret.name}'`);
        }
        if (fromMap && !(configMaps.has(fromMap.name) && mapKeys(configMaps.get(fromMap.name)).has(fromMap.key))) {
          errors.push(`${at}: ${variable.name} needs key '${fromMap.key}' of ConfigMap '${fromMap.name}'`);
        }
      }
      for (const mount of container.volumeMounts ?? []) {
        const volume = volumes.get(mount.name);
        if (!volume) {
          errors.push(`${at}: mounts volume '${mount.name}', which the pod does not declare`);
        } else if (mount.subPath && volume.configMap?.items &&
                   !volume.configMap.items.some((item) => item.path === mount.subPath)) {
          errors.push(`${at}: subPath '${mount.subPath}' is not a path of volume '${mount.name}'`);
        }
      }
    }
  }

  for (const { file, object } of docs.filter((d) => d.object.kind === "Service")) {
    const where = `${file}: Service ${object.metadata?.name}`;
    const pods = workloads.filter((w) => matches(object.spec?.selector, w.object.spec?.template?.metadata?.labels));
    if (pods.length === 0) {
      errors.push(`${where}: selector matches no pod template`);
      continue;
    }
    const containerPorts = pods.flatMap((w) => w.object.spec.template.spec?.containers ?? []).flatMap((c) => c.ports ?? []);
    for (const port of object.spec?.ports ?? []) {
      const target = port.targetPort ?? port.port;
      const known = containerPorts.some((p) => (typeof target === "string" ? p.name === target : p.containerPort === target));
      if (!known) errors.push(`${where}: port '${port.name}' targets '${target}', which no selected container declares`);
    }
  }
  return errors;
}

export async function checkManifests(dir) {
  const { docs, errors } = loadManifests(dir);
  if (errors.length > 0) return errors;
  return [...checkKustomization(docs), ...(await checkSchemas(docs)), ...(await checkFieldNames(docs)), ...checkReferences(docs)];
}
